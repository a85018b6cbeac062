// SPDX-License-Identifier: GPL-3.0-or-later
#include "SegmentConformation.h"

#include "BoundingBox.h"
#include "SegmentRules.h"
#include "UnionFind.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <unordered_map>

namespace omesh
{
SegmentSet::SegmentSet(const FeatureSegments& f)
  : points(f.points)
  , corner(f.points.size(), 1)
  , inputEnds_(f.segments.size())
  , cluster_(f.segments.size())
  , subsOfInput_(f.segments.size())
  , scale_(f.segments.size(), { 1.0, 1.0 })
{
  std::vector<std::vector<int>> incident(f.points.size());
  for (size_t s = 0; s < f.segments.size(); ++s)
  {
    subs.push_back({ f.segments[s][0], f.segments[s][1], static_cast<int>(s) });
    subsOfInput_[s] = { static_cast<int>(s) };
    inputEnds_[s] = f.segments[s];
    incident[f.segments[s][0]].push_back(static_cast<int>(s));
    incident[f.segments[s][1]].push_back(static_cast<int>(s));
  }
  // Clusters at each vertex: the segments there joined, transitively, by angles below kClusterAngle.
  for (size_t v = 0; v < incident.size(); ++v)
  {
    const std::vector<int>& at = incident[v];
    if (at.size() < 2)
      continue;
    UnionFind clusters(at.size());
    auto far = [&](int seg) { return points[inputEnds_[seg][0] == static_cast<int>(v) ? inputEnds_[seg][1] : inputEnds_[seg][0]]; };
    for (size_t i = 0; i < at.size(); ++i)
      for (size_t j = i + 1; j < at.size(); ++j)
        if (angleAt(points[v], far(at[i]), far(at[j])) < kClusterAngle)
          clusters.join(i, j);
    for (size_t i = 0; i < at.size(); ++i)
    {
      const int end = inputEnds_[at[i]][0] == static_cast<int>(v) ? 0 : 1;
      int rank = 0;
      for (size_t j = 0; j < at.size(); ++j)
        if (i != j && clusters.find(i) == clusters.find(j))
        {
          cluster_[at[i]][end].push_back(at[j]);
          rank += j < i;
        }
      scale_[at[i]][end] = 1.0 + 1e-9 * rank;
    }
  }
}

double SegmentSet::shellDistance(int input, int at, double cut) const
{
  return cut * scale_[input][inputEnds_[input][0] == at ? 0 : 1];
}

int SegmentSet::add(const Vec3& p)
{
  points.push_back(p);
  corner.push_back(0);
  return static_cast<int>(points.size()) - 1;
}

int SegmentSet::split(size_t s, double t)
{
  const auto [a, b, input] = subs[s];
  const int m = add(lerp(points[a], points[b], t));
  subs[s] = { a, m, input };
  subs.push_back({ m, b, input });
  if (static_cast<size_t>(input) < subsOfInput_.size())
    subsOfInput_[input].push_back(static_cast<int>(subs.size()) - 1);
  return m;
}

std::vector<std::pair<int, double>> SegmentSet::mirrorSplits(size_t s, double t) const
{
  std::vector<std::pair<int, double>> out;
  const auto [a, b, input] = subs[s];
  if (static_cast<size_t>(input) >= inputEnds_.size())
    return out;
  const Vec3 m = lerp(points[a], points[b], t);
  const double r0 = norm(m - points[inputEnds_[input][0]]), r1 = norm(m - points[inputEnds_[input][1]]);
  const int side = r0 <= r1 ? 0 : 1;
  const int apex = inputEnds_[input][side];
  const double shell = std::min(r0, r1) / scale_[input][side];
  for (int j : cluster_[input][side])
  {
    const int jSide = inputEnds_[j][0] == apex ? 0 : 1;
    const int other = inputEnds_[j][1 - jSide];
    const double rho = shell * scale_[j][jSide];
    const double len = norm(points[other] - points[apex]);
    if (rho > 0.5 * len)
      continue; // beyond the segment's half near the apex: its other end's business
    const double tol = 1e-9 * len;
    for (int x : subsOfInput_[j])
    {
      const double da = norm(points[subs[x][0]] - points[apex]), db = norm(points[subs[x][1]] - points[apex]);
      if (rho > std::min(da, db) + tol && rho < std::max(da, db) - tol)
      {
        if (std::min(std::abs(rho - da), std::abs(rho - db)) >= 0.25 * length(s))
          out.emplace_back(x, (rho - da) / (db - da));
        break;
      }
    }
  }
  return out;
}

namespace
{
/// Segment points in a uniform hash grid: "is there a point in this ball" without looking at
/// every point (dense feature lines have tens of thousands).
class PointGrid
{
public:
  PointGrid(const std::vector<Vec3>& points, double cell)
    : points_(points)
    , cell_(cell > 0 && std::isfinite(cell) ? cell : 1.0)
  {
    for (size_t p = 0; p < points.size(); ++p)
      add(static_cast<int>(p));
  }
  void add(int p) { cells_[key(coord(points_[p]))].push_back(p); }

  /// A point other than the segment's ends `skipA`, `skipB` encroaches the segment ab.
  bool anyEncroaching(const Vec3& a, const Vec3& b, int skipA, int skipB) const
  {
    auto inside = [&](int p) { return p != skipA && p != skipB && rules::encroaches(a, b, points_[p]); };
    const Vec3 centre = 0.5 * (a + b);
    const double r = std::sqrt(0.25 * dot(b - a, b - a));
    const std::array<long long, 3> lo = coord(centre - Vec3{ r, r, r }), hi = coord(centre + Vec3{ r, r, r });
    const double cells = double(hi[0] - lo[0] + 1) * double(hi[1] - lo[1] + 1) * double(hi[2] - lo[2] + 1);
    if (cells > static_cast<double>(points_.size()))
    {
      for (size_t p = 0; p < points_.size(); ++p)
        if (inside(static_cast<int>(p)))
          return true;
      return false;
    }
    for (long long i = lo[0]; i <= hi[0]; ++i)
      for (long long j = lo[1]; j <= hi[1]; ++j)
        for (long long k = lo[2]; k <= hi[2]; ++k)
        {
          const auto it = cells_.find(key({ i, j, k }));
          if (it != cells_.end())
            for (int p : it->second)
              if (inside(p))
                return true;
        }
    return false;
  }

private:
  std::array<long long, 3> coord(const Vec3& p) const
  {
    return { static_cast<long long>(std::floor(p.x / cell_)), static_cast<long long>(std::floor(p.y / cell_)),
      static_cast<long long>(std::floor(p.z / cell_)) };
  }
  static std::uint64_t key(const std::array<long long, 3>& c)
  {
    return (static_cast<std::uint64_t>(c[0]) * 73856093ULL) ^ (static_cast<std::uint64_t>(c[1]) * 19349663ULL) ^
      (static_cast<std::uint64_t>(c[2]) * 83492791ULL);
  }
  const std::vector<Vec3>& points_;
  double cell_;
  std::unordered_map<std::uint64_t, std::vector<int>> cells_;
};
}

namespace
{
/// T1.1 on the input segments: every segment at a star vertex p_i gets a point at l_min,i / 3
/// from p_i (scaled as the shells of its small-angle cluster), where l_min,i is the shortest of
/// the segments trimmed there, but only a segment that meets another there at less than 90
/// degrees (FeatureSegments::endsBelowRightAngle): every vertex of a polyline through a smooth curve (a found
/// curve, a resampled rim) has none, and its trims cut each chord in three; at a junction a curve
/// leaving at 90 degrees or more from every other one keeps its end whole, and a short such curve
/// no longer sets the others' trims. Calls `check` at every segment.
void trimAtStarVertices(SegmentSet& set, const FeatureSegments& f, const std::function<void()>& check)
{
  const std::vector<std::array<bool, 2>> trimmed = f.endsBelowRightAngle();
  std::vector<double> lmin(f.points.size(), std::numeric_limits<double>::infinity());
  for (size_t s = 0; s < f.segments.size(); ++s)
    for (int side = 0; side < 2; ++side)
      if (trimmed[s][side])
        lmin[f.segments[s][side]] = std::min(lmin[f.segments[s][side]], f.length(s));
  for (size_t s = 0, n = set.subs.size(); s < n; ++s)
  {
    if (check)
      check();
    for (int side = 0; side < 2; ++side)
    {
      const int a = set.subs[s][0], b = set.subs[s][1];
      const int at = side == 0 ? a : b;
      const int input = set.subs[s][2];
      if (!trimmed[input][f.segments[input][0] == at ? 0 : 1])
        continue;
      const std::optional<double> t =
        rules::trimAtStarVertexT11(set.length(s), set.shellDistance(set.subs[s][2], at, lmin[at] / 3.0));
      if (!t)
        continue;
      // split so that the piece touching `at` has length cut; keep sub-segment s as the piece
      // away from already-trimmed ends
      if (at == a)
      {
        set.split(s, *t); // s = (a, m), new = (m, b)
        std::swap(set.subs[s], set.subs.back()); // s = (m, b) continues, the trimmed piece is done
      }
      else
        set.split(s, 1.0 - *t); // s = (a, m), new = (m, b) is the trimmed piece
      ++set.trims;
    }
  }
}

/// T1.2 on the segments alone: midpoint splits until no sub-segment is encroached by a segment
/// point (or longer than its input segment's `edgeSizes`), mirrored in small-angle clusters. Returns
/// false when it stopped at `maxPoints`. Calls `check` at every sub-segment it looks at.
bool splitEncroached(SegmentSet& set, const std::vector<double>& edgeSizes, size_t maxPoints, std::vector<std::string>& warnings,
  const std::function<void()>& check)
{
  std::vector<double> lengths;
  for (size_t s = 0; s < set.subs.size(); ++s)
    lengths.push_back(set.length(s));
  std::nth_element(lengths.begin(), lengths.begin() + lengths.size() / 2, lengths.end());
  PointGrid grid(set.points, lengths.empty() ? 1.0 : lengths[lengths.size() / 2]);
  // Encroachment splits stop at 1/64 of the shortest piece after T1.1, as in the mesher's
  // refinement: a point almost on another segment (closer than rounding to it) otherwise drew
  // midpoint splits towards it without end (found by fuzzing).
  const double floor = (lengths.empty() ? 0.0 : *std::min_element(lengths.begin(), lengths.end())) / 64.0;
  std::vector<char> given; // encroached but at the floor: left as it is
  size_t unresolved = 0;
  auto splitAt = [&](size_t s, double t) {
    grid.add(set.split(s, t));
    ++set.splits;
  };
  bool changed = true;
  while (changed)
  {
    changed = false;
    for (size_t s = 0; s < set.subs.size(); ++s)
    {
      if (check)
        check();
      if (s < given.size() && given[s])
        continue;
      const Vec3 a = set.points[set.subs[s][0]], b = set.points[set.subs[s][1]];
      const double edgeSize = edgeSizes[set.subs[s][2]];
      const bool tooLong = edgeSize > 0 && dot(b - a, b - a) > edgeSize * edgeSize;
      const bool encroached = !tooLong && grid.anyEncroaching(a, b, set.subs[s][0], set.subs[s][1]);
      const std::optional<double> t = rules::splitEncroachedT12(a, b, encroached, edgeSize, floor);
      if (!t)
      {
        if (encroached)
        {
          given.resize(set.subs.size(), 0);
          given[s] = 1;
          ++unresolved;
        }
        continue;
      }
      if (set.points.size() >= maxPoints)
      {
        warnings.push_back("feature lines: segment refinement stopped at " + std::to_string(maxPoints) +
          " points (segments meeting at small angles keep encroaching each other)");
        return false;
      }
      const auto mirrors = set.mirrorSplits(s, *t);
      splitAt(s, *t);
      for (const auto& [x, u] : mirrors)
      {
        splitAt(static_cast<size_t>(x), u);
        ++set.mirrored;
      }
      changed = true;
    }
  }
  if (unresolved)
    warnings.push_back("feature lines: " + std::to_string(unresolved) +
      " sub-segment(s) stay encroached by a point closer to them than 1/64 of the shortest segment piece; "
      "splitting stopped there");
  return true;
}
}

SegmentSet conformSegments(const FeatureSegments& f, const std::vector<double>& edgeSizes, size_t maxPoints,
  std::vector<std::string>& warnings, const std::function<void()>& check)
{
  SegmentSet set(f);
  trimAtStarVertices(set, f, check);
  splitEncroached(set, edgeSizes, maxPoints, warnings, check);
  return set;
}

SegmentSet conformSegments(const FeatureSegments& f, double edgeSize, size_t maxPoints, std::vector<std::string>& warnings,
  const std::function<void()>& check)
{
  return conformSegments(f, std::vector<double>(f.segments.size(), edgeSize), maxPoints, warnings, check);
}
}
