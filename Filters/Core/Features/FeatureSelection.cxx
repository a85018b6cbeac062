// SPDX-License-Identifier: GPL-3.0-or-later
#include "FeatureSelection.h"

#include "FeatureMerge.h"
#include "HierarchicalOracle.h"
#include "MeshCriteria.h"
#include "UnionFind.h"

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
/// Automatic curves leaving a vertex at less than this (degrees) share a trunk (selectFeatures), as
/// given lines do in simplifyFeatureNetwork (FeatureNetworkTolerances::minAngle).
constexpr double kTrunkAngle = 30.0;

/// The parameters in (0, 1), ascending, where segment pq passes through some input's boundary: not
/// region changes, since the line lies on its own input's boundary, which decides all along it (a
/// closed set).
std::vector<double> boundaryCrossings(const HierarchicalOracle& oracle, const Vec3& p, const Vec3& q)
{
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
  return ts;
}

/// The segment of `A` nearest to x, closer than `reach`; -1: none.
int nearestSegment(const FeatureSegments& A, const Vec3& x, double reach)
{
  int best = -1;
  double nearest = reach;
  for (size_t s = 0; s < A.segments.size(); ++s)
  {
    const double dist = distanceToSegment(x, A.points[A.segments[s][0]], A.points[A.segments[s][1]]);
    if (dist < nearest)
    {
      nearest = dist;
      best = static_cast<int>(s);
    }
  }
  return best;
}

/// The first point of `points` within `same` of x; -1: none.
int pointNear(const std::vector<Vec3>& points, const Vec3& x, double same)
{
  int xi = -1;
  for (size_t i = 0; i < points.size() && xi < 0; ++i)
    if (norm(points[i] - x) <= same)
      xi = static_cast<int>(i);
  return xi;
}

/// Splits the automatic segment `best` at the new point x: in the segments (the piece from x on is
/// appended, with the same source) and in each curve of `automatic.lines` where it passes that
/// segment (its first pass).
void splitAutomaticSegment(FeatureLines& automatic, int best, const Vec3& x)
{
  auto& A = automatic.segments;
  const int ai = static_cast<int>(A.points.size());
  A.points.push_back(x);
  const int start = A.segments[best][0], end = A.segments[best][1];
  A.segments[best][1] = ai;
  A.segments.push_back({ ai, end });
  if (!A.source.empty())
    A.source.push_back(A.source[best]);
  for (FeatureLine& l : automatic.lines)
    for (size_t k = 0; k + 1 < l.points.size(); ++k)
      if ((l.points[k] == start && l.points[k + 1] == end) || (l.points[k] == end && l.points[k + 1] == start))
      {
        l.points.insert(l.points.begin() + static_cast<long>(k) + 1, ai);
        break;
      }
}

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
    for (double t : boundaryCrossings(oracle, p, q))
    {
      Vec3 x = lerp(p, q, t);
      const int best = nearestSegment(A, x, reach);
      if (best < 0 || norm(x - given.points[from]) <= same || norm(x - q) <= same)
        continue;
      auto& s = A.segments[best];
      const int atEnd = norm(A.points[s[0]] - x) <= same ? 0 : norm(A.points[s[1]] - x) <= same ? 1 : -1;
      // A point of another given line there (a part's corner on which this line ends in a T, as a
      // box's edge through a wedge's corner on the cut plane) is the crossing: the line is split at
      // that point, and the curve's end, found a sampling error (1e-9) off it, moved onto it. Split
      // at the found end instead, the line had a second vertex 2e-9 beside the corner: the segment
      // level's pieces there, 1/64 of the shortest of which is its split floor, fell to 0.003 and
      // the wedge's 18.4 degree corner refined to micro tetrahedra (Benchmarks/cad_defects item 4).
      int xi = pointNear(given.points, x, same);
      split.push_back({ from, xi >= 0 ? xi : static_cast<int>(given.points.size()) });
      if (xi >= 0)
      {
        from = xi;
        if (atEnd >= 0)
        {
          A.points[s[atEnd]] = given.points[xi]; // one point: same coordinates
          continue;
        }
        x = given.points[xi];
      }
      else
      {
        // into the curve: the end of its nearest segment if that is the point, else a new vertex
        xi = static_cast<int>(given.points.size());
        from = xi;
        if (atEnd >= 0)
        {
          given.points.push_back(A.points[s[atEnd]]); // one point: same coordinates
          continue;
        }
        given.points.push_back(x);
      }
      splitAutomaticSegment(automatic, best, x);
    }
    split.push_back({ from, seg[1] });
  }
  given.segments = std::move(split);
}

/// Whether chord a-b lies within eps of `segments` (of `points`) at its ends, its middle and its
/// quarters: a curve found along a given line.
bool runsAlong(const std::vector<std::array<int, 2>>& segments, const std::vector<Vec3>& points, const Vec3& a,
  const Vec3& b, double eps)
{
  const auto near = [&](const Vec3& x) {
    for (const auto& g : segments)
      if (distanceToSegment(x, points[g[0]], points[g[1]]) <= eps)
        return true;
    return false;
  };
  return near(a) && near(b) && near(lerp(a, b, 0.5)) && near(lerp(a, b, 0.25)) && near(lerp(a, b, 0.75));
}

bool runsAlong(const FeatureSegments& lines, const Vec3& a, const Vec3& b, double eps)
{
  return runsAlong(lines.segments, lines.points, a, b, eps);
}

/// Automatic curves that run along given lines (the tray's bottom rim, a sharp edge of the implant,
/// is also where implant, bone and the cut meet) would be near-duplicate segments the segment level
/// splits without end: those within `eps` of the given lines all along are dropped, and the ends of
/// the kept ones that lie on a given line are moved onto it and become vertices of it (joined, not
/// a T: the given line keeps its course, the automatic end moves by at most `eps`).
/// Segments [0, firstAutomatic) are given. Returns the number dropped; firstAutomatic is updated.
std::size_t dropAutomaticAlongGiven(FeatureSegments& f, std::size_t& firstAutomatic, double eps)
{
  std::vector<std::array<int, 2>> given(f.segments.begin(), f.segments.begin() + static_cast<long>(firstAutomatic));
  std::vector<std::array<int, 2>> automatic(f.segments.begin() + static_cast<long>(firstAutomatic), f.segments.end());
  // the sources (FeatureSegments::source, when tracked) go with the segments: a piece of a split keeps its own
  const bool tracked = !f.source.empty();
  std::vector<int> givenSource, keptSource;
  if (tracked)
    givenSource.assign(f.source.begin(), f.source.begin() + static_cast<long>(firstAutomatic));
  auto nearestGiven = [&](const Vec3& x) {
    std::pair<double, int> best{ HUGE_VAL, -1 };
    for (size_t g = 0; g < given.size(); ++g)
      best = std::min(best, { distanceToSegment(x, f.points[given[g][0]], f.points[given[g][1]]), static_cast<int>(g) });
    return best;
  };
  std::size_t dropped = 0;
  std::vector<std::array<int, 2>> kept;
  for (size_t k = 0; k < automatic.size(); ++k)
  {
    const auto& s = automatic[k];
    const Vec3 a = f.points[s[0]], b = f.points[s[1]];
    if (runsAlong(given, f.points, a, b, eps))
      ++dropped;
    else
    {
      kept.push_back(s);
      if (tracked)
        keptSource.push_back(f.source[firstAutomatic + k]);
    }
  }
  if (dropped == 0)
    return 0;
  // the kept automatic ends on a given line: that line's end point, or a new vertex of it
  std::set<int> ends;
  for (const auto& s : kept)
    ends.insert({ s[0], s[1] });
  std::map<int, int> remap;
  for (int v : ends)
  {
    const Vec3 x = f.points[v];
    const auto [d, g] = nearestGiven(x);
    if (g < 0 || d > eps)
      continue;
    const int g0 = given[g][0], g1 = given[g][1];
    if (v == g0 || v == g1)
      continue;
    if (norm(f.points[g0] - x) <= eps || norm(f.points[g1] - x) <= eps)
    {
      remap[v] = norm(f.points[g0] - x) <= norm(f.points[g1] - x) ? g0 : g1;
      continue;
    }
    const double t = segmentParameter(x, f.points[g0], f.points[g1]);
    f.points[v] = lerp(f.points[g0], f.points[g1], t); // onto the given line, which stays straight
    given[g] = { g0, v };
    given.push_back({ v, g1 });
    if (tracked)
      givenSource.push_back(givenSource[g]);
  }
  for (auto& s : kept)
    for (int& v : s)
      if (auto it = remap.find(v); it != remap.end())
        v = it->second;
  std::vector<std::array<int, 2>> nonEmpty;
  std::vector<int> nonEmptySource;
  for (size_t k = 0; k < kept.size(); ++k)
    if (kept[k][0] != kept[k][1])
    {
      nonEmpty.push_back(kept[k]);
      if (tracked)
        nonEmptySource.push_back(keptSource[k]);
    }
  firstAutomatic = given.size();
  f.segments = std::move(given);
  f.segments.insert(f.segments.end(), nonEmpty.begin(), nonEmpty.end());
  if (tracked)
  {
    f.source = std::move(givenSource);
    f.source.insert(f.source.end(), nonEmptySource.begin(), nonEmptySource.end());
  }
  return dropped;
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
  // a tenth of the facet distance (the curves' deviation aimed at), not the half that
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
    // chords up to the facet size: the mesher splits them to the edge size (T1.2)
    if (v.facetSize > 0)
      o.materialChordLength[m] = v.facetSize;
    if (v.facetDistance > 0)
      o.materialTolerance[m] = 0.1 * v.facetDistance;
  }
  o.creaseChordLength = HUGE_VAL; // an input's own points: chords as long as the tolerance allows
  o.tolerance = g.facetDistance > 0 ? 0.1 * g.facetDistance : 0.05 * finest;
  o.spacing = 0.5 * finest;
  return o;
}

namespace
{
/// The curves found, triple lines first, then creases, then the longest first.
std::vector<const FeatureLine*> triplesThenLongest(const FeatureLines& automatic)
{
  const FeatureSegments& A = automatic.segments;
  std::vector<const FeatureLine*> order;
  std::map<const FeatureLine*, double> length;
  for (const FeatureLine& l : automatic.lines)
  {
    order.push_back(&l);
    for (size_t k = 0; k + 1 < l.points.size(); ++k)
      length[&l] += norm(A.points[l.points[k + 1]] - A.points[l.points[k]]);
  }
  // Creases before the other curves of as many materials: a crease's vertices lie on the input's
  // own edge, while a cut rim on a cut plane through that input's face is the same curve found by
  // the search, a rounding error off it, with chords cutting its corners; kept first, the rim left
  // chords of a hundredth of the grid step beside the box's corners (they set the segment level's
  // split floor, 1/64 of the shortest piece, so an acute corner elsewhere refined to micro
  // tetrahedra: Benchmarks/cad_defects item 4).
  std::stable_sort(order.begin(), order.end(), [&](const FeatureLine* a, const FeatureLine* b) {
    if (a->materials.size() != b->materials.size())
      return a->materials.size() > b->materials.size();
    if (a->crease != b->crease)
      return a->crease;
    return length[a] > length[b];
  });
  return order;
}

/// Curves that still leave a vertex at a very small angle (crossing at a few degrees) share a
/// trunk, as simplifyFeatureNetwork does for given lines: the longer segment is replaced by the
/// shorter one and the chord from its far end (moving that curve by at most sin(angle) times the
/// shorter segment). Wider angles are the segment level's (clusters below 30 degrees). Returns the
/// number of segments rerouted. `f` has no own edge sizes (automatic segments have none).
/// Segments marked in `keep` (those along given lines, which the selection drops later) are
/// neither rerouted nor a trunk: rerouted, such a crease (a part's given edge found again, 15
/// degrees from another part's edge at a shared corner) came back as a chord 0.4 off both edges
/// that no given line covers, meeting the given edge at 5 degrees (Benchmarks/cad_defects item 7).
std::size_t shareTrunks(FeatureSegments& f, const std::vector<char>& keep = {})
{
  std::size_t shared = 0;
  for (int round = 0; round < 16; ++round)
  {
    std::vector<std::vector<size_t>> at(f.points.size());
    for (size_t k = 0; k < f.segments.size(); ++k)
      for (int v : f.segments[k])
        at[v].push_back(k);
    bool changed = false;
    std::vector<char> touched(f.segments.size(), 0);
    for (size_t v = 0; v < at.size(); ++v)
      for (size_t i = 0; i < at[v].size(); ++i)
        for (size_t j = i + 1; j < at[v].size(); ++j)
        {
          const size_t si = at[v][i], sj = at[v][j];
          if (touched[si] || touched[sj] || (!keep.empty() && (keep[si] || keep[sj])))
            continue;
          const int a = f.segments[si][0] == int(v) ? f.segments[si][1] : f.segments[si][0];
          const int b = f.segments[sj][0] == int(v) ? f.segments[sj][1] : f.segments[sj][0];
          if (a == b || !(angleAt(f.points[v], f.points[a], f.points[b]) < kTrunkAngle))
            continue;
          const Vec3 pv = f.points[v];
          const bool iShorter = norm(f.points[a] - pv) <= norm(f.points[b] - pv);
          f.segments[iShorter ? sj : si] = iShorter ? std::array<int, 2>{ a, b } : std::array<int, 2>{ b, a };
          touched[si] = touched[sj] = 1;
          ++shared;
          changed = true;
        }
    if (!changed)
      break;
  }
  // A trunk can be a segment the curves have already (a wedge's 18.4 degree corner: its long crease
  // rerouted over the short one is the third crease): one copy only, not two that "meet at 0
  // degrees".
  std::set<std::array<int, 2>> seen;
  std::vector<std::array<int, 2>> unique;
  std::vector<int> uniqueSource;
  for (size_t k = 0; k < f.segments.size(); ++k)
    if (seen.insert({ std::min(f.segments[k][0], f.segments[k][1]), std::max(f.segments[k][0], f.segments[k][1]) }).second)
    {
      unique.push_back(f.segments[k]);
      if (!f.source.empty())
        uniqueSource.push_back(f.source[k]);
    }
  f.segments = std::move(unique);
  if (!f.source.empty())
    f.source = std::move(uniqueSource);
  return shared;
}

/// Curves closer than half a grid step along a stretch (a tray's rim beside a label map's
/// staircase rim on the same plane, arms leaving a junction at a few degrees) are one line for
/// the search and could only be meshed with tetrahedra that small: taken in order (triple lines,
/// then the longest first), a curve's segments that run along the curves already taken are
/// dropped and its ends there moved onto them, so such curves share a trunk and part at a wider
/// angle (shareTrunks). The small-angle warnings then describe the lines as they are now.
void dropNearDuplicateCurves(FeatureSelection& out, double smallAngle, const FeatureSegments& given)
{
  FeatureSegments& A = out.automatic.segments;
  FeatureSegments taken;
  taken.points = A.points;
  // each segment's source: the index of its curve in out.automatic.lines (labelOrigins tags by it)
  for (const FeatureLine* l : triplesThenLongest(out.automatic))
  {
    std::size_t first = taken.segments.size();
    for (size_t k = 0; k + 1 < l->points.size(); ++k)
      if (l->points[k] != l->points[k + 1])
      {
        taken.segments.push_back({ l->points[k], l->points[k + 1] });
        taken.source.push_back(static_cast<int>(l - out.automatic.lines.data()));
      }
    if (first > 0)
      out.droppedNearDuplicate += dropAutomaticAlongGiven(taken, first, 0.5 * out.automatic.spacing);
  }
  std::vector<char> alongGiven(taken.segments.size(), 0);
  if (!given.segments.empty())
    for (size_t k = 0; k < taken.segments.size(); ++k)
      alongGiven[k] = runsAlong(given, taken.points[taken.segments[k][0]], taken.points[taken.segments[k][1]],
        0.5 * out.automatic.spacing);
  out.trunksShared += shareTrunks(taken, alongGiven);
  A = std::move(taken);
  out.warnings.erase(std::remove_if(out.warnings.begin(), out.warnings.end(),
                       [](const std::string& w) { return w.rfind("feature lines meet", 0) == 0; }),
    out.warnings.end());
  out.automatic.smallAngles = findSmallFeatureAngles(A, smallAngle, out.warnings);
  if (out.droppedNearDuplicate > 0)
    out.warnings.push_back("feature lines: " + std::to_string(out.droppedNearDuplicate) +
      " segment(s) of the lines found run within half a grid step of other curves found and were dropped (they share their trunk)");
}

/// Whether a tetrahedron can hold the chord a-b as an edge: material touches every piece of it, the
/// halves and quarters the segment level would split it into down to a 64th of the chord and to a
/// quarter of the search's grid step (a rim bending inwards can leave the chord just outside along
/// a stretch its quarters do not see, touchesMaterial's offsets growing with the piece: the
/// segment level then splits towards it without end).
bool holdableChord(const HierarchicalOracle& oracle, const Vec3& a, const Vec3& b, double step)
{
  const double length = norm(b - a);
  for (int parts = 1; parts <= 64 || (parts <= 256 && length / parts > 0.25 * step); parts *= 2)
    for (int k = 0; k < parts; ++k)
      if (!oracle.touchesMaterial(lerp(a, b, double(k) / parts), lerp(a, b, double(k + 1) / parts)))
        return false;
  return true;
}

/// Of the segments kept, the connected pieces that touch a dropped segment and are shorter, all
/// together, than the search's grid step: remnants of a curve whose rest had no material next to
/// it (a voxel corner's sliver where the rim bends inwards). The search cannot tell such a stretch,
/// and the segment level splits towards its loose ends without end. Returns their indices in `kept`.
std::set<std::size_t> shortRemnants(const FeatureSegments& A, const std::vector<std::array<int, 2>>& kept,
  const std::set<int>& droppedEnds, double step)
{
  UnionFind pieces(A.points.size());
  for (const auto& s : kept)
    pieces.join(s[0], s[1]);
  std::vector<double> length(A.points.size(), 0.0);
  std::vector<bool> touching(A.points.size(), false);
  for (const auto& s : kept)
  {
    length[pieces.find(s[0])] += norm(A.points[s[1]] - A.points[s[0]]);
    for (int v : s)
      if (droppedEnds.count(v))
        touching[pieces.find(v)] = true;
  }
  std::set<std::size_t> remnants;
  for (size_t k = 0; k < kept.size(); ++k)
    if (const std::size_t r = pieces.find(kept[k][0]); touching[r] && length[r] < step)
      remnants.insert(k);
  return remnants;
}

/// The automatic segments appended to out.segments (a point with the coordinates of a given one, a
/// shared crossing, is that point). A segment on the domain's outer boundary where the rim bends
/// inwards (a label map's rim on a cut plane is a staircase at voxel scale) has no material next
/// to it along some stretch (holdableChord): no tetrahedron can hold it as an edge. Dropped, as
/// simplifyFeatureNetwork drops given segments that leave the domain, and with them the remnants
/// of their curves shorter than a grid step (shortRemnants).
void appendAutomatic(const HierarchicalOracle& oracle, FeatureSelection& out)
{
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
  const FeatureSegments& A = out.automatic.segments;
  const double step = out.automatic.spacing;
  std::vector<std::array<int, 2>> kept;
  std::vector<size_t> keptIndex; // in A.segments
  std::set<int> droppedEnds;
  for (size_t k = 0; k < A.segments.size(); ++k)
  {
    const auto& s = A.segments[k];
    if (holdableChord(oracle, A.points[s[0]], A.points[s[1]], step))
    {
      kept.push_back(s);
      keptIndex.push_back(k);
    }
    else
      droppedEnds.insert({ s[0], s[1] });
  }
  std::size_t unmeshable = A.segments.size() - kept.size();
  const std::set<std::size_t> remnants = unmeshable > 0 ? shortRemnants(A, kept, droppedEnds, step) : std::set<std::size_t>{};
  out.segments.source.assign(out.segments.segments.size(), -1); // the given ones: no curve found
  for (size_t k = 0; k < kept.size(); ++k)
    if (!remnants.count(k))
    {
      out.segments.segments.push_back({ index[kept[k][0]], index[kept[k][1]] });
      out.segments.source.push_back(A.source.empty() ? -1 : A.source[keptIndex[k]]);
    }
  unmeshable += remnants.size();
  if (unmeshable > 0)
  {
    out.droppedUnmeshable = unmeshable;
    std::string w = "feature lines: " + std::to_string(unmeshable - remnants.size()) +
      " segment(s) of the lines found where inputs meet have no material next to them (a rim of the domain's outer "
      "boundary bending inwards) and were dropped: no tetrahedron could hold them as an edge";
    if (!remnants.empty())
      w += "; so were " + std::to_string(remnants.size()) +
        " segment(s) left between them, pieces shorter than the search's grid step";
    out.warnings.push_back(w);
  }
}

/// Given lines win: the automatic segments (from `firstAutomatic` on) that run along given lines
/// (the search cannot tell curves closer than its grid step apart, nor can the mesh at twice
/// that), then those that cross given ones, are dropped.
void dropAutomaticAtGiven(FeatureSelection& out, std::size_t firstAutomatic)
{
  std::size_t automaticFrom = firstAutomatic;
  if (const std::size_t along = dropAutomaticAlongGiven(out.segments, automaticFrom, 0.5 * out.automatic.spacing))
  {
    out.droppedAlongGiven = along;
    out.warnings.push_back("feature lines: " + std::to_string(along) +
      " segment(s) of the lines found where inputs meet run along given lines and were dropped (the given ones are kept)");
  }
  std::set<std::size_t> drop;
  for (const auto& [s, t] : out.segments.crossingPairs())
  {
    const bool sAuto = s >= automaticFrom, tAuto = t >= automaticFrom;
    if (sAuto != tAuto)
      drop.insert(sAuto ? s : t);
  }
  if (drop.empty())
    return;
  std::vector<std::array<int, 2>> kept;
  std::vector<int> keptSource;
  for (std::size_t s = 0; s < out.segments.segments.size(); ++s)
    if (!drop.count(s))
    {
      kept.push_back(out.segments.segments[s]);
      if (!out.segments.source.empty())
        keptSource.push_back(out.segments.source[s]);
    }
  out.segments.segments = std::move(kept);
  out.segments.source = std::move(keptSource);
  out.droppedAutomatic = drop.size();
  out.warnings.push_back("feature lines: " + std::to_string(drop.size()) +
    " segment(s) of the lines found where inputs meet cross given lines and were dropped (the given ones are kept)");
}

/// A point this close to a given line lies on it (the pieces of given segments after splits and
/// merges, to rounding).
double onGivenLine(const HierarchicalOracle& oracle)
{
  return 1e-9 * norm(oracle.bounds().size());
}

/// selectFeatures without the given lines' own edge sizes: `given.edgeSizes` is empty unless
/// `source` is Given or None (nothing below runs then), so the steps that drop, split and move
/// segments keep no edge-size vector; selectFeatures carries the sizes onto the result.
FeatureSelection selectWithoutEdgeSizes(const HierarchicalOracle& oracle, const FeatureSegments& given,
  FeatureSource source, const MaterialCriteria& criteria, double creaseAngle,
  const std::function<bool(double)>& progress)
{
  FeatureSelection out;
  if (source == FeatureSource::Given || source == FeatureSource::Both)
    out.segments = given;
  if (source != FeatureSource::Automatic && source != FeatureSource::Both)
    return out;
  FeatureLineOptions options = featureLineOptions(oracle, criteria);
  options.creaseAngle = creaseAngle;
  options.progress = progress;
  out.automatic = findFeatureLines(oracle, options);
  out.warnings = out.automatic.warnings;
  dropNearDuplicateCurves(out, options.smallAngle, out.segments);
  if (!out.segments.empty())
    shareCrossings(oracle, out.segments, out.automatic);
  const std::size_t firstAutomatic = out.segments.segments.size();
  appendAutomatic(oracle, out);
  if (firstAutomatic > 0 && !out.automatic.segments.empty())
    dropAutomaticAtGiven(out, firstAutomatic);
  if (out.droppedUnmeshable + out.droppedAlongGiven + out.droppedNearDuplicate + out.droppedAutomatic > 0)
    mergeFeatureSegments(out.segments); // drops the points no segment uses any more
  return out;
}

/// The mesher inserts every point of its lines as a corner vertex, used or not. A vertex of a
/// dropped curve stays a point (mergeFeatureSegments keeps the points when it merges nothing), and
/// those of the curves found along a given line lie on that line to the search's 1e-10: a point a
/// hair beside a segment that is no vertex of it, which every split of that segment encroaches
/// (micro tetrahedra on a rim chord at the found vertices). Dropped, in order.
void dropUnusedPoints(FeatureSegments& f)
{
  std::vector<int> renumber(f.points.size(), -1);
  for (const auto& s : f.segments)
    for (int v : s)
      renumber[v] = 0;
  std::vector<Vec3> points;
  for (size_t i = 0; i < f.points.size(); ++i)
    if (renumber[i] == 0)
    {
      renumber[i] = static_cast<int>(points.size());
      points.push_back(f.points[i]);
    }
  if (points.size() == f.points.size())
    return;
  for (auto& s : f.segments)
    for (int& v : s)
      v = renumber[v];
  f.points = std::move(points);
}

/// Origins. The steps above drop, split, reroute and renumber segments, so a segment's origin is
/// told by geometry, but not by its distance to the curves found: a trunk shared at a small angle
/// (shareTrunks) is a chord between two curves that lies off both (0.42 mm off on a study case,
/// its crease chords being long), and lines given but not selected (Automatic with from_surface)
/// must not count. So: Automatic, every segment was found; Given, none; Both, a segment on a given
/// line (its midpoint within onGivenLine of one: pieces of given segments, split or merged, stay on
/// them) is given, any other was found. Where a given line and a curve found coincide, given wins:
/// dropAutomaticAlongGiven kept the given segment (the user's course and own edge size) and dropped
/// the found one. A found segment's materials are those of the curve it came from
/// (FeatureSegments::source, carried through every step above: a piece of a split, a segment whose
/// end was moved onto another curve and a shared trunk keep theirs), not of the curve nearest its
/// midpoint: a trunk or a moved end can lie nearer another curve, whose materials it would take.
/// The nearest rule remains for a segment without a source. The sources are cleared
/// afterwards: the network simplification numbers its own.
void labelOrigins(FeatureSelection& out, const FeatureSegments& given, FeatureSource source, const HierarchicalOracle& oracle)
{
  const auto& P = out.segments.points;
  out.origin.assign(out.segments.segments.size(), {});
  if (source != FeatureSource::Automatic && source != FeatureSource::Both)
    return;
  const auto& A = out.automatic.segments.points;
  const double onLine = source == FeatureSource::Both ? onGivenLine(oracle) : 0.0;
  for (size_t s = 0; s < out.segments.segments.size(); ++s)
  {
    const Vec3 m = lerp(P[out.segments.segments[s][0]], P[out.segments.segments[s][1]], 0.5);
    bool onGiven = false;
    for (size_t g = 0; source == FeatureSource::Both && g < given.segments.size() && !onGiven; ++g)
      onGiven = distanceToSegment(m, given.points[given.segments[g][0]], given.points[given.segments[g][1]]) <= onLine;
    if (onGiven)
      continue;
    out.origin[s].automatic = true;
    const FeatureLine *line = nullptr, *nearestLine = nullptr;
    if (const int from = s < out.segments.source.size() ? out.segments.source[s] : -1;
        from >= 0 && from < static_cast<int>(out.automatic.lines.size()))
      line = &out.automatic.lines[from];
    double nearest = HUGE_VAL;
    for (size_t i = 0; !line && i < out.automatic.lines.size(); ++i)
      for (size_t k = 0; k + 1 < out.automatic.lines[i].points.size(); ++k)
      {
        const auto& l = out.automatic.lines[i].points;
        if (const double d = distanceToSegment(m, A[l[k]], A[l[k + 1]]); d < nearest)
          nearest = d, nearestLine = &out.automatic.lines[i];
      }
    if (!line)
      line = nearestLine;
    for (size_t k = 0; line && k < line->materials.size() && k < 4; ++k)
      out.origin[s].materials[k] = line->materials[k];
  }
  out.segments.source.clear();
  out.automatic.segments.source.clear();
}
}

FeatureSelection selectFeatures(const HierarchicalOracle& oracle, const FeatureSegments& given, FeatureSource source,
  const MaterialCriteria& criteria, double creaseAngle, const std::function<bool(double)>& progress)
{
  checkCreaseAngle(creaseAngle, "feature lines: creaseAngle"); // also when not searching: bad input is an error
  // Points no segment uses are dropped, whatever the source (dropUnusedPoints): the points of
  // curves the selection dropped, and stray points of given polylines, which the mesher would
  // otherwise insert as corner vertices.
  if (given.edgeSizes.empty() || source == FeatureSource::Given || source == FeatureSource::None)
  {
    FeatureSelection out = selectWithoutEdgeSizes(oracle, given, source, criteria, creaseAngle, progress);
    if (source == FeatureSource::None)
      out.segments.edgeSizes.clear();
    dropUnusedPoints(out.segments);
    labelOrigins(out, given, source, oracle);
    return out;
  }
  // Given lines split where automatic ones meet them (shared crossings, automatic ends moved onto
  // them) keep their own edge sizes on every piece, found by geometry (the given lines keep their
  // course); the automatic lines have none (their materials' count). Segments dropped or merged
  // leave no entry behind: the sizes are assigned to the final segments, one each.
  FeatureSegments bare = given;
  bare.edgeSizes.clear();
  FeatureSelection out = selectWithoutEdgeSizes(oracle, bare, source, criteria, creaseAngle, progress);
  dropUnusedPoints(out.segments);
  transferEdgeSizes(given, out.segments, onGivenLine(oracle));
  labelOrigins(out, given, source, oracle);
  return out;
}
}
