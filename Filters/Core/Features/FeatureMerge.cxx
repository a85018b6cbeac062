// SPDX-License-Identifier: GPL-3.0-or-later
#include "FeatureMerge.h"

#include "InputError.h"
#include "UnionFind.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/box_intersection_d.h>

#include <algorithm>
#include <map>
#include <cmath>
#include <optional>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <tuple>

namespace omesh
{
namespace
{
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Box = CGAL::Box_intersection_d::Box_with_info_d<double, 3, std::size_t>;
}

namespace
{
/// Segments with their own edge sizes and sources (FeatureSegments::edgeSizes, source: empty
/// when not given).
struct Pieces
{
  std::vector<std::array<int, 2>> segments;
  std::vector<std::optional<double>> edgeSizes;
  std::vector<int> source;
  /// `sourced`: the segments have sources (a source may be -1, "none": it is kept in step too)
  void add(const std::array<int, 2>& s, std::optional<double> size, bool sized, int from, bool sourced)
  {
    segments.push_back(s);
    if (sized)
      edgeSizes.push_back(size);
    if (sourced)
      source.push_back(from);
  }
};

int sourceOf(const FeatureSegments& f, std::size_t s) { return f.source.empty() ? -1 : f.source[s]; }

K::Point_3 point3(const FeatureSegments& f, int i) { return { f.points[i].x, f.points[i].y, f.points[i].z }; }

/// The box of half-width `tolerance` around feature point i.
Box pointBox(const FeatureSegments& f, std::size_t i, double tolerance)
{
  const Vec3& p = f.points[i];
  double lo[3] = { p.x - tolerance, p.y - tolerance, p.z - tolerance };
  double hi[3] = { p.x + tolerance, p.y + tolerance, p.z + tolerance };
  return Box(lo, hi, i);
}

/// The bounding box of the segment ab grown by `pad` on every side, with `info`.
Box segmentBox(const Vec3& a, const Vec3& b, std::size_t info, double pad = 0.0)
{
  double lo[3] = { std::min(a.x, b.x) - pad, std::min(a.y, b.y) - pad, std::min(a.z, b.z) - pad };
  double hi[3] = { std::max(a.x, b.x) + pad, std::max(a.y, b.y) + pad, std::max(a.z, b.z) + pad };
  return Box(lo, hi, info);
}

/// Each segment split at its `inner` points (in any order; repeats and points at its ends give no
/// piece), the pieces in order along it with the segment's own edge size and source.
void splitSegmentsAt(FeatureSegments& f, std::vector<std::vector<int>>& inner)
{
  const bool sized = !f.edgeSizes.empty(), sourced = !f.source.empty();
  FeatureSegments out;
  for (std::size_t s = 0; s < f.segments.size(); ++s)
  {
    std::vector<int> chain{ f.segments[s][0] };
    const Vec3 a = f.points[f.segments[s][0]], d = f.points[f.segments[s][1]] - a;
    std::vector<int>& in = inner[s];
    std::sort(in.begin(), in.end(), [&](int i, int j) { return dot(f.points[i] - a, d) < dot(f.points[j] - a, d); });
    in.erase(std::unique(in.begin(), in.end()), in.end());
    chain.insert(chain.end(), in.begin(), in.end());
    chain.push_back(f.segments[s][1]);
    for (std::size_t k = 0; k + 1 < chain.size(); ++k)
      if (chain[k] != chain[k + 1] && norm(f.points[chain[k + 1]] - f.points[chain[k]]) > 0.0)
      {
        out.segments.push_back({ chain[k], chain[k + 1] });
        if (sized)
          out.edgeSizes.push_back(f.edgeSizes[s]);
        if (sourced)
          out.source.push_back(f.source[s]);
      }
  }
  f.segments = std::move(out.segments);
  f.edgeSizes = std::move(out.edgeSizes);
  f.source = std::move(out.source);
}

/// One line given twice (repeated or overlapping) keeps its own edge size; two different ones
/// are a contradiction (InputError naming the line and both values).
std::optional<double> sameEdgeSize(const FeatureSegments& f, const std::array<int, 2>& s, std::optional<double> mine,
  std::optional<double> other)
{
  if (mine && other && *mine != *other)
  {
    const Vec3 &a = f.points[s[0]], &b = f.points[s[1]];
    std::ostringstream o;
    o << "feature lines: segment (" << a.x << ", " << a.y << ", " << a.z << ") - (" << b.x << ", " << b.y << ", "
      << b.z << ") gets EdgeSize " << *mine << " and " << *other
      << " from two lines that overlap there (give each piece of a line one edge size)";
    throw InputError(o.str());
  }
  return mine ? mine : other;
}

/// How close two feature points, or a point and a segment, must be to be taken for the same place:
/// a few hundred ulps of the lines' extent. CAD parts meshed together share edges only up to
/// rounding (a 16-gon's side edge computed with cos/sin lies 4.4e-16 off the box edge it was placed
/// on); exact predicates call such lines parallel, not overlapping, so they stayed two lines, each
/// splitting the other's sub-segments (their points encroach each other's diametral balls) without
/// end: 55k segment points in 30 s, or CGAL failing on a refinement point that repeats a vertex.
constexpr double kSamePlaceRelative = 1e-10;

double samePlaceTolerance(const FeatureSegments& f)
{
  if (f.points.empty())
    return 0.0;
  Vec3 lo = f.points[0], hi = f.points[0];
  for (const Vec3& p : f.points)
  {
    lo = { std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z) };
    hi = { std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z) };
  }
  return kSamePlaceRelative * norm(hi - lo);
}

/// 1. One vertex per place: identical coordinates, or closer than `tolerance` (the first listed
/// point's coordinates are kept).
void mergeRepeatedPoints(FeatureSegments& f, double tolerance, FeatureMergeCounts& counts)
{
  std::map<std::tuple<double, double, double>, int> byCoordinates;
  std::vector<int> same(f.points.size());
  for (std::size_t i = 0; i < f.points.size(); ++i)
  {
    const Vec3& p = f.points[i];
    auto [it, inserted] = byCoordinates.emplace(std::make_tuple(p.x, p.y, p.z), static_cast<int>(i));
    same[i] = it->second;
    counts.mergedPoints += !inserted;
  }
  if (tolerance > 0)
  {
    std::vector<Box> boxes;
    for (const auto& [xyz, i] : byCoordinates)
      boxes.push_back(pointBox(f, static_cast<std::size_t>(i), tolerance));
    UnionFind near(f.points.size());
    CGAL::box_self_intersection_d(boxes.begin(), boxes.end(), [&](const Box& a, const Box& b) {
      if (norm(f.points[a.info()] - f.points[b.info()]) <= tolerance)
        near.join(std::max(a.info(), b.info()), std::min(a.info(), b.info()));
    });
    std::map<std::size_t, int> first; // each near group's first listed point
    for (const auto& [xyz, i] : byCoordinates)
    {
      auto [it, inserted] = first.emplace(near.find(i), i);
      if (!inserted)
        it->second = std::min(it->second, i);
    }
    for (const auto& [xyz, i] : byCoordinates)
      if (const int keep = first[near.find(i)]; keep != i)
      {
        ++counts.mergedPoints;
        if (!counts.withinRounding++)
          counts.firstWithinRounding = f.points[i];
      }
    for (std::size_t i = 0; i < f.points.size(); ++i)
      same[i] = first[near.find(same[i])];
  }
  for (auto& s : f.segments)
    s = { same[s[0]], same[s[1]] };
}

/// 3c. A segment that passes within `tolerance` of a feature point other than its ends is split
/// there: a line that runs along another up to rounding then shares its vertices, and the pieces
/// they both cover become repeated segments (step 2 again). Edge sizes and sources go with the pieces.
void splitAtPointsOnSegments(FeatureSegments& f, double tolerance, FeatureMergeCounts& counts)
{
  if (tolerance <= 0 || f.segments.empty())
    return;
  std::vector<bool> used(f.points.size(), false);
  for (const auto& s : f.segments)
    used[s[0]] = used[s[1]] = true;
  std::vector<Box> points, segments;
  for (std::size_t i = 0; i < f.points.size(); ++i)
    if (used[i])
      points.push_back(pointBox(f, i, tolerance));
  for (std::size_t k = 0; k < f.segments.size(); ++k)
    segments.push_back(segmentBox(f.points[f.segments[k][0]], f.points[f.segments[k][1]], k));
  std::vector<std::vector<int>> inner(f.segments.size()); // points to split each segment at
  CGAL::box_intersection_d(segments.begin(), segments.end(), points.begin(), points.end(),
    [&](const Box& sb, const Box& pb) {
      const auto& s = f.segments[sb.info()];
      const int v = static_cast<int>(pb.info());
      if (v == s[0] || v == s[1] || s[0] == s[1])
        return;
      const Vec3 &a = f.points[s[0]], &b = f.points[s[1]], &p = f.points[v];
      const Vec3 d = b - a;
      const double t = dot(p - a, d) / dot(d, d);
      if (!(t > 0 && t < 1) || norm(p - (a + t * d)) > tolerance || norm(p - a) <= tolerance ||
        norm(p - b) <= tolerance)
        return;
      if (CGAL::collinear(point3(f, s[0]), point3(f, v), point3(f, s[1])))
        return; // exactly on it: a T, which splitAtCrossings splits (and counts)
      inner[sb.info()].push_back(v);
    });
  if (std::all_of(inner.begin(), inner.end(), [](const std::vector<int>& in) { return in.empty(); }))
    return;
  splitSegmentsAt(f, inner); // sorts each segment's points along it
  for (const std::vector<int>& in : inner)
    if (!in.empty())
    {
      counts.splitSegments += 1;
      if (!counts.withinRounding++)
        counts.firstWithinRounding = f.points[in.front()];
    }
}

/// 2. Repeated segments (either direction); zero-length ones stay for validate to name.
Pieces withoutRepeatedSegments(const FeatureSegments& f, FeatureMergeCounts& counts)
{
  const bool sized = !f.edgeSizes.empty();
  std::map<std::pair<int, int>, std::size_t> seen;
  Pieces unique;
  unique.segments.reserve(f.segments.size());
  for (std::size_t k = 0; k < f.segments.size(); ++k)
  {
    const auto& s = f.segments[k];
    if (s[0] != s[1])
    {
      const auto [it, inserted] = seen.emplace(std::make_pair(std::min(s[0], s[1]), std::max(s[0], s[1])), unique.segments.size());
      if (!inserted)
      {
        ++counts.duplicates;
        if (sized)
          unique.edgeSizes[it->second] = sameEdgeSize(f, s, unique.edgeSizes[it->second], f.edgeSize(k));
        continue;
      }
    }
    unique.add(s, f.edgeSize(k), sized, sourceOf(f, k), !f.source.empty()); // a repeated one: the first's
  }
  return unique;
}

/// 3a. Collinear overlapping segments, grouped by union-find; `overlaps` marks the segments in a group.
UnionFind overlapGroups(const FeatureSegments& f, const std::vector<std::array<int, 2>>& unique, std::vector<bool>& overlaps)
{
  const auto P = [&](int i) { return point3(f, i); };
  std::vector<Box> boxes;
  boxes.reserve(unique.size());
  for (std::size_t s = 0; s < unique.size(); ++s)
    boxes.push_back(segmentBox(f.points[unique[s][0]], f.points[unique[s][1]], s));
  UnionFind groups(unique.size());
  overlaps.assign(unique.size(), false);
  auto check = [&](const Box& x, const Box& y) {
    const auto& a = unique[x.info()];
    const auto& b = unique[y.info()];
    if (a[0] == a[1] || b[0] == b[1])
      return;
    if (!CGAL::collinear(P(a[0]), P(a[1]), P(b[0])) || !CGAL::collinear(P(a[0]), P(a[1]), P(b[1])))
      return;
    bool overlap;
    int shared = -1;
    for (int i : a)
      for (int j : b)
        if (i == j)
          shared = i;
    if (shared >= 0)
    {
      const int pa = a[0] == shared ? a[1] : a[0];
      const int pb = b[0] == shared ? b[1] : b[0];
      overlap = CGAL::angle(P(pa), P(shared), P(pb)) == CGAL::ACUTE;
    }
    else
      overlap = CGAL::do_intersect(K::Segment_3(P(a[0]), P(a[1])), K::Segment_3(P(b[0]), P(b[1])));
    if (overlap)
    {
      groups.join(x.info(), y.info());
      overlaps[x.info()] = overlaps[y.info()] = true;
    }
  };
  CGAL::box_self_intersection_d(boxes.begin(), boxes.end(), check);
  return groups;
}

/// 3b. The segments with each overlap group replaced by its union; a piece keeps the own edge
/// size of the segments covering it.
Pieces withOverlapsMerged(const FeatureSegments& f, const Pieces& pieces, FeatureMergeCounts& counts)
{
  const std::vector<std::array<int, 2>>& unique = pieces.segments;
  const bool sized = !pieces.edgeSizes.empty();
  const auto sizeOf = [&](std::size_t s) { return sized ? pieces.edgeSizes[s] : std::nullopt; };
  const bool sourced = !pieces.source.empty();
  const auto sourceOf = [&](std::size_t s) { return sourced ? pieces.source[s] : -1; };
  std::vector<bool> overlaps;
  UnionFind groups = overlapGroups(f, unique, overlaps);
  std::map<std::size_t, std::vector<std::size_t>> members;
  Pieces merged;
  merged.segments.reserve(unique.size());
  for (std::size_t s = 0; s < unique.size(); ++s)
  {
    if (overlaps[s])
      members[groups.find(s)].push_back(s);
    else
      merged.add(unique[s], sizeOf(s), sized, sourceOf(s), sourced);
  }
  for (const auto& [root, group] : members)
  {
    ++counts.overlapGroups;
    counts.overlapping += group.size();
    const Vec3 origin = f.points[unique[group[0]][0]];
    const Vec3 direction = f.points[unique[group[0]][1]] - origin;
    const auto param = [&](int v) { return dot(f.points[v] - origin, direction); };
    std::vector<int> vertices;
    for (std::size_t s : group)
      for (int v : unique[s])
        vertices.push_back(v);
    std::sort(vertices.begin(), vertices.end());
    vertices.erase(std::unique(vertices.begin(), vertices.end()), vertices.end());
    std::sort(vertices.begin(), vertices.end(), [&](int a, int b) { return param(a) < param(b); });
    for (std::size_t k = 0; k + 1 < vertices.size(); ++k)
    {
      const double mid = 0.5 * (param(vertices[k]) + param(vertices[k + 1]));
      const std::array<int, 2> piece{ vertices[k], vertices[k + 1] };
      bool covered = false;
      std::optional<double> size;
      int from = -1; // the first covering segment's
      for (std::size_t s : group)
      {
        const double t0 = param(unique[s][0]), t1 = param(unique[s][1]);
        if (std::min(t0, t1) < mid && mid < std::max(t0, t1))
        {
          if (!covered)
            from = sourceOf(s);
          covered = true;
          size = sameEdgeSize(f, piece, size, sizeOf(s));
        }
      }
      if (covered)
        merged.add(piece, size, sized, from, sourced);
    }
  }
  return merged;
}

/// 4. `pieces` as f's segments, without the points no segment uses.
void keepUsedPoints(FeatureSegments& f, Pieces pieces)
{
  std::vector<std::array<int, 2>>& segments = pieces.segments;
  std::vector<int> renumber(f.points.size(), -1);
  std::vector<Vec3> points;
  for (auto& s : segments)
    for (int& v : s)
    {
      if (renumber[v] < 0)
      {
        renumber[v] = static_cast<int>(points.size());
        points.push_back(f.points[v]);
      }
      v = renumber[v];
    }
  f.points = std::move(points);
  f.segments = std::move(segments);
  f.edgeSizes = std::move(pieces.edgeSizes);
  f.source = std::move(pieces.source);
}
}

namespace
{
/// The parameters of the closest points of the lines through segments s (a0 + sa u) and t
/// (b0 + tb w); false where they are parallel (|u x w| <= 1e-12 |u| |w|).
bool closestParameters(const FeatureSegments& f, std::size_t s, std::size_t t, double& sa, double& tb)
{
  const auto& a = f.segments[s];
  const auto& b = f.segments[t];
  const Vec3 u = f.points[a[1]] - f.points[a[0]], w = f.points[b[1]] - f.points[b[0]];
  const Vec3 r = f.points[a[0]] - f.points[b[0]];
  const double uu = dot(u, u), uw = dot(u, w), ww = dot(w, w), ur = dot(u, r), wr = dot(w, r);
  const double den = uu * ww - uw * uw; // |u x w|^2
  if (!(den > 1e-24 * uu * ww))
    return false;
  sa = (uw * wr - ww * ur) / den;
  tb = (uu * wr - uw * ur) / den;
  return true;
}

/// Pairs of segments without a shared end that pass within `tolerance` of each other at a point
/// inside both (farther than `tolerance` from every end), though exact predicates see no contact:
/// two parts' edges that cross only up to rounding (a 16-gon's side edge 4.4e-16 off the box edge
/// it crosses). Left alone, the mesher splits both near that place, each split point encroaching the
/// other segment, down to two vertices 4e-16 apart and flat tetrahedra between them. (Near contacts
/// at an end are splitAtPointsOnSegments'.)
std::vector<std::pair<std::size_t, std::size_t>> nearCrossingPairs(const FeatureSegments& f, double tolerance)
{
  std::vector<std::pair<std::size_t, std::size_t>> pairs;
  if (tolerance <= 0)
    return pairs;
  std::vector<Box> boxes;
  boxes.reserve(f.segments.size());
  for (std::size_t k = 0; k < f.segments.size(); ++k)
    boxes.push_back(segmentBox(f.points[f.segments[k][0]], f.points[f.segments[k][1]], k, tolerance));
  CGAL::box_self_intersection_d(boxes.begin(), boxes.end(), [&](const Box& x, const Box& y) {
    const std::size_t s = x.info(), t = y.info();
    const auto& a = f.segments[s];
    const auto& b = f.segments[t];
    if (a[0] == b[0] || a[0] == b[1] || a[1] == b[0] || a[1] == b[1])
      return;
    double sa = 0, tb = 0;
    if (!closestParameters(f, s, t, sa, tb))
      return;
    const double lu = f.length(s), lw = f.length(t);
    if (!(sa * lu > tolerance && (1 - sa) * lu > tolerance && tb * lw > tolerance && (1 - tb) * lw > tolerance))
      return;
    const Vec3 p = f.points[a[0]] + sa * (f.points[a[1]] - f.points[a[0]]);
    const Vec3 q = f.points[b[0]] + tb * (f.points[b[1]] - f.points[b[0]]);
    if (norm(p - q) <= tolerance)
      pairs.emplace_back(std::min(s, t), std::max(s, t));
  });
  return pairs;
}

/// 5. Segments that cross or touch at a point inside one of them split there, so that lines meet
/// only at shared points: the sharp edges of two parts meeting face to face cross on the shared
/// face (an X) or end on each other's edges (a T), and each part's vtkFeatureEdges knows nothing
/// of the other. A T is split at the stem's end (exactly: the end lies on the bar, exact
/// predicates); an X at a new point, the one nearest both lines. Pieces keep their segment's own
/// edge size and source. Returns the number of pairs split. Parallel contacts (overlaps the
/// merge left) are not touched: validate names them. Segments crossing within `tolerance`
/// (nearCrossingPairs) are an X too.
std::size_t splitAtCrossings(FeatureSegments& f, double tolerance)
{
  std::vector<std::pair<std::size_t, std::size_t>> crossing = f.crossingPairs();
  const std::vector<std::pair<std::size_t, std::size_t>> near = nearCrossingPairs(f, tolerance);
  crossing.insert(crossing.end(), near.begin(), near.end());
  std::sort(crossing.begin(), crossing.end());
  crossing.erase(std::unique(crossing.begin(), crossing.end()), crossing.end());
  if (crossing.empty())
    return 0;
  std::vector<std::vector<int>> inner(f.segments.size()); // points to split each segment at
  std::size_t split = 0;
  for (const auto& [s, t] : crossing)
  {
    const auto& a = f.segments[s];
    const auto& b = f.segments[t];
    double sa = 0, tb = 0;
    if (!closestParameters(f, s, t, sa, tb))
      continue; // parallel: an overlap, not a crossing
    bool tee = false;
    for (const auto& [end, other, at] : { std::tuple{ a, b, t }, std::tuple{ b, a, s } })
      for (int v : end)
        if (v != other[0] && v != other[1] && CGAL::collinear(point3(f, other[0]), point3(f, v), point3(f, other[1])) &&
          CGAL::collinear_are_strictly_ordered_along_line(point3(f, other[0]), point3(f, v), point3(f, other[1])))
        {
          inner[at].push_back(v);
          tee = true;
        }
    if (!tee)
    {
      // the X's point: the closest points of the two lines, halfway
      const Vec3 u = f.points[a[1]] - f.points[a[0]], w = f.points[b[1]] - f.points[b[0]];
      const Vec3 x = 0.5 * ((f.points[a[0]] + std::clamp(sa, 0.0, 1.0) * u) + (f.points[b[0]] + std::clamp(tb, 0.0, 1.0) * w));
      const int id = static_cast<int>(f.points.size());
      f.points.push_back(x);
      inner[s].push_back(id);
      inner[t].push_back(id);
    }
    ++split;
  }
  if (split)
    splitSegmentsAt(f, inner);
  return split;
}
}

FeatureMergeCounts mergeFeatureSegments(FeatureSegments& f)
{
  FeatureMergeCounts counts;
  for (const Vec3& p : f.points)
    if (!isFinite(p))
      return counts;
  for (const auto& s : f.segments)
    for (int v : s)
      if (v < 0 || v >= static_cast<int>(f.points.size()))
        return counts; // validate names it
  if (!f.source.empty() && f.source.size() != f.segments.size())
    throw std::logic_error("mergeFeatureSegments: " + std::to_string(f.source.size()) + " sources for " +
      std::to_string(f.segments.size()) + " segments"); // internal: whoever rebuilt them lost track
  if (!f.edgeSizes.empty())
  {
    if (f.edgeSizes.size() != f.segments.size())
      return counts; // validate names it
    for (const auto& e : f.edgeSizes)
      if (e && !(std::isfinite(*e) && *e >= 0))
        return counts;
  }
  // after a split, again: an X point may repeat a point of a third line, pieces may overlap (the
  // merge steps always run after the last split)
  const double tolerance = samePlaceTolerance(f);
  for (int round = 0;; ++round)
  {
    FeatureMergeCounts c;
    mergeRepeatedPoints(f, tolerance, c);
    const Pieces unique = withoutRepeatedSegments(f, c);
    Pieces merged = withOverlapsMerged(f, unique, c);
    if (c.changed())
      keepUsedPoints(f, std::move(merged)); // else as given: same points, same order
    // lines that run along each other only up to rounding (exact predicates: parallel, neither
    // overlapping nor crossing): split at each other's points, their common pieces repeat
    splitAtPointsOnSegments(f, tolerance, c);
    if (c.splitSegments)
      keepUsedPoints(f, withoutRepeatedSegments(f, c));
    counts.mergedPoints += c.mergedPoints;
    counts.duplicates += c.duplicates;
    counts.overlapping += c.overlapping;
    counts.overlapGroups += c.overlapGroups;
    counts.splitSegments += c.splitSegments;
    if (c.withinRounding && !counts.withinRounding)
      counts.firstWithinRounding = c.firstWithinRounding;
    counts.withinRounding += c.withinRounding;
    if (round == 3)
      break;
    const std::size_t split = splitAtCrossings(f, tolerance);
    counts.crossings += split;
    if (!split)
      break;
  }
  return counts;
}
}
