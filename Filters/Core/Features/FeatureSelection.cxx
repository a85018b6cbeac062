// SPDX-License-Identifier: GPL-3.0-or-later
#include "FeatureSelection.h"

#include "FeatureMerge.h"
#include "HierarchicalOracle.h"
#include "MeshCriteria.h"

#include <algorithm>
#include <map>
#include <set>

namespace omesh
{
const char* toString(FeatureSource s)
{
  switch (s)
  {
    case FeatureSource::None:
      return "None";
    case FeatureSource::Given:
      return "Given";
    case FeatureSource::Automatic:
      return "Automatic";
    case FeatureSource::Both:
      return "Both";
  }
  return "?";
}

namespace
{
/// Where a given line (a sharp edge of the implant) passes through another input's boundary and an
/// automatic curve passes nearby (the implant's entry curve), both get that exact point as one
/// vertex: the given segment is split there, and the curve's nearest segment too.
void shareCrossings(const HierarchicalOracle& oracle, FeatureSegments& given, FeatureLines& automatic)
{
  auto& A = automatic.segments;
  const double reach = automatic.spacing; // the curves' chords lie within a grid step of the curve
  const double same = 1e-9 * norm(oracle.bounds().size());
  std::vector<std::array<int, 2>> split;
  for (const auto& seg : given.segments)
  {
    const Vec3 p = given.points[seg[0]], q = given.points[seg[1]];
    int from = seg[0];
    // Where the line passes through some input's boundary: not region changes, since the line
    // lies on its own input's boundary, which decides all along it (a closed set).
    std::vector<double> ts;
    for (const auto& d : oracle.domains())
    {
      std::vector<double> own;
      d->crossings(p, q, own);
      for (double t : own)
        if (t > 0 && t < 1 && d->material(lerp(p, q, std::max(0.0, t - 1e-7))) != d->material(lerp(p, q, std::min(1.0, t + 1e-7))))
          ts.push_back(t);
    }
    std::sort(ts.begin(), ts.end());
    for (double t : ts)
    {
      const Vec3 x = lerp(p, q, t);
      // the nearest automatic segment
      int best = -1;
      double nearest = reach;
      for (size_t s = 0; s < A.segments.size(); ++s)
      {
        const Vec3 a = A.points[A.segments[s][0]], d = A.points[A.segments[s][1]] - a;
        const double u = std::clamp(dot(x - a, d) / dot(d, d), 0.0, 1.0);
        const double dist = norm(x - (a + u * d));
        if (dist < nearest)
        {
          nearest = dist;
          best = static_cast<int>(s);
        }
      }
      if (best < 0 || norm(x - given.points[from]) <= same || norm(x - q) <= same)
        continue;
      // into the curve: the end of its nearest segment if that is the point, else a new vertex
      auto& s = A.segments[best];
      const int xi = static_cast<int>(given.points.size());
      split.push_back({ from, xi });
      from = xi;
      if (norm(A.points[s[0]] - x) <= same || norm(A.points[s[1]] - x) <= same)
      {
        given.points.push_back(A.points[s[norm(A.points[s[0]] - x) <= same ? 0 : 1]]); // one point: same coordinates
        continue;
      }
      given.points.push_back(x);
      const int ai = static_cast<int>(A.points.size());
      A.points.push_back(x);
      const int end = s[1];
      s[1] = ai;
      A.segments.push_back({ ai, end });
      for (FeatureLine& l : automatic.lines)
        for (size_t k = 0; k + 1 < l.points.size(); ++k)
          if ((l.points[k] == s[0] && l.points[k + 1] == end) || (l.points[k] == end && l.points[k + 1] == s[0]))
          {
            l.points.insert(l.points.begin() + static_cast<long>(k) + 1, ai);
            break;
          }
    }
    split.push_back({ from, seg[1] });
  }
  given.segments = std::move(split);
}
}

FeatureLineOptions featureLineOptions(const HierarchicalOracle& oracle, const MaterialCriteria& criteria)
{
  FeatureLineOptions o;
  auto lengthOf = [&](const MeshCriteria::Values& v) {
    return v.edgeSize > 0 ? v.edgeSize : v.facetSize > 0 ? v.facetSize : 0.0;
  };
  const MeshCriteria::Values g = criteria.globalValues();
  o.maxSegmentLength = lengthOf(g) > 0 ? lengthOf(g) : norm(oracle.bounds().size()) / 40.0;
  double finest = o.maxSegmentLength;
  // a tenth of the facet distance (issue 13's aim for the curves' deviation), not the half that
  // resampling given lines uses: these chords are the mesh's edges on the curve. Per material, so
  // that the implant's 0.1 mm does not make the bone's rims a staircase of 0.01 mm pieces.
  for (const auto& [m, unused] : criteria.perMaterial)
  {
    const MeshCriteria::Values v = criteria.of(m);
    if (lengthOf(v) > 0)
    {
      o.materialSegmentLength[m] = lengthOf(v);
      finest = std::min(finest, lengthOf(v));
    }
    if (v.facetDistance > 0)
      o.materialTolerance[m] = 0.1 * v.facetDistance;
  }
  o.tolerance = g.facetDistance > 0 ? 0.1 * g.facetDistance : 0.05 * finest;
  o.spacing = 0.5 * finest;
  return o;
}

FeatureSelection selectFeatures(const HierarchicalOracle& oracle, const FeatureSegments& given, FeatureSource source,
  const MaterialCriteria& criteria, const std::function<bool(double)>& progress)
{
  FeatureSelection out;
  if (source == FeatureSource::Given || source == FeatureSource::Both)
    out.segments = given;
  if (source != FeatureSource::Automatic && source != FeatureSource::Both)
    return out;
  FeatureLineOptions options = featureLineOptions(oracle, criteria);
  options.progress = progress;
  out.automatic = findFeatureLines(oracle, options);
  out.warnings = out.automatic.warnings;
  if (!out.segments.empty())
    shareCrossings(oracle, out.segments, out.automatic);
  // Appended; a point with the coordinates of a given one (a shared crossing) is that point.
  const std::size_t firstAutomatic = out.segments.segments.size();
  std::map<std::array<double, 3>, int> givenPoint;
  for (size_t i = 0; i < out.segments.points.size(); ++i)
    givenPoint.emplace(std::array<double, 3>{ out.segments.points[i].x, out.segments.points[i].y, out.segments.points[i].z },
      static_cast<int>(i));
  std::vector<int> index;
  for (const Vec3& p : out.automatic.segments.points)
  {
    auto it = givenPoint.find({ p.x, p.y, p.z });
    if (it != givenPoint.end())
      index.push_back(it->second);
    else
    {
      index.push_back(static_cast<int>(out.segments.points.size()));
      out.segments.points.push_back(p);
    }
  }
  // A segment on the domain's outer boundary where the rim bends inwards (a label map's rim on a
  // cut plane is a staircase at voxel scale) has no material next to it, nor have the halves and
  // quarters the segment level would split it into: no tetrahedron can hold it as an edge. Dropped,
  // as simplifyFeatureNetwork drops given segments that leave the domain.
  std::size_t unmeshable = 0;
  for (auto s : out.automatic.segments.segments)
  {
    const Vec3 a = out.automatic.segments.points[s[0]], b = out.automatic.segments.points[s[1]];
    bool meshable = true;
    for (int parts = 1; parts <= 4 && meshable; parts *= 2)
      for (int k = 0; k < parts && meshable; ++k)
        meshable = oracle.touchesMaterial(lerp(a, b, double(k) / parts), lerp(a, b, double(k + 1) / parts));
    if (meshable)
      out.segments.segments.push_back({ index[s[0]], index[s[1]] });
    else
      ++unmeshable;
  }
  if (unmeshable > 0)
  {
    out.droppedUnmeshable = unmeshable;
    out.warnings.push_back("feature lines: " + std::to_string(unmeshable) +
      " segment(s) of the lines found where inputs meet have no material next to them (a rim of the domain's outer "
      "boundary bending inwards) and were dropped: no tetrahedron could hold them as an edge");
  }
  if (firstAutomatic == 0 || out.automatic.segments.empty())
  {
    if (unmeshable > 0)
      mergeFeatureSegments(out.segments); // drops the points no segment uses any more
    return out;
  }
  // Given lines win over automatic ones that cross them.
  std::set<std::size_t> drop;
  for (const auto& [s, t] : out.segments.crossingPairs())
  {
    const bool sAuto = s >= firstAutomatic, tAuto = t >= firstAutomatic;
    if (sAuto != tAuto)
      drop.insert(sAuto ? s : t);
  }
  if (drop.empty())
  {
    if (unmeshable > 0)
      mergeFeatureSegments(out.segments);
    return out;
  }
  std::vector<std::array<int, 2>> kept;
  for (std::size_t s = 0; s < out.segments.segments.size(); ++s)
    if (!drop.count(s))
      kept.push_back(out.segments.segments[s]);
  out.segments.segments = std::move(kept);
  out.droppedAutomatic = drop.size();
  out.warnings.push_back("feature lines: " + std::to_string(drop.size()) +
    " segment(s) of the lines found where inputs meet cross given lines and were dropped (the given ones are kept)");
  mergeFeatureSegments(out.segments); // drops the points no segment uses any more
  return out;
}
}
