// SPDX-License-Identifier: GPL-3.0-or-later
#include "FeatureMerge.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/box_intersection_d.h>

#include <algorithm>
#include <map>
#include <numeric>
#include <set>
#include <tuple>

namespace omesh
{
namespace
{
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Box = CGAL::Box_intersection_d::Box_with_info_d<double, 3, std::size_t>;

struct UnionFind
{
  std::vector<std::size_t> parent;
  explicit UnionFind(std::size_t n)
    : parent(n)
  {
    std::iota(parent.begin(), parent.end(), 0);
  }
  std::size_t find(std::size_t x)
  {
    while (parent[x] != x)
      x = parent[x] = parent[parent[x]];
    return x;
  }
  void join(std::size_t a, std::size_t b) { parent[find(a)] = find(b); }
};
}

namespace
{
/// 1. One vertex per coordinate triple.
void mergeRepeatedPoints(FeatureSegments& f, FeatureMergeCounts& counts)
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
  for (auto& s : f.segments)
    s = { same[s[0]], same[s[1]] };
}

/// 2. Repeated segments (either direction); zero-length ones stay for validate to name.
std::vector<std::array<int, 2>> withoutRepeatedSegments(const FeatureSegments& f, FeatureMergeCounts& counts)
{
  std::set<std::pair<int, int>> seen;
  std::vector<std::array<int, 2>> unique;
  unique.reserve(f.segments.size());
  for (const auto& s : f.segments)
  {
    if (s[0] != s[1] && !seen.emplace(std::min(s[0], s[1]), std::max(s[0], s[1])).second)
    {
      ++counts.duplicates;
      continue;
    }
    unique.push_back(s);
  }
  return unique;
}

/// 3a. Collinear overlapping segments, grouped by union-find; `overlaps` marks the segments in a group.
UnionFind overlapGroups(const FeatureSegments& f, const std::vector<std::array<int, 2>>& unique, std::vector<bool>& overlaps)
{
  const auto P = [&](int i) { return K::Point_3(f.points[i].x, f.points[i].y, f.points[i].z); };
  std::vector<Box> boxes;
  boxes.reserve(unique.size());
  for (std::size_t s = 0; s < unique.size(); ++s)
  {
    const Vec3& a = f.points[unique[s][0]];
    const Vec3& b = f.points[unique[s][1]];
    double lo[3] = { std::min(a.x, b.x), std::min(a.y, b.y), std::min(a.z, b.z) };
    double hi[3] = { std::max(a.x, b.x), std::max(a.y, b.y), std::max(a.z, b.z) };
    boxes.emplace_back(lo, hi, s);
  }
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

/// 3b. The segments with each overlap group replaced by its union.
std::vector<std::array<int, 2>> withOverlapsMerged(
  const FeatureSegments& f, const std::vector<std::array<int, 2>>& unique, FeatureMergeCounts& counts)
{
  std::vector<bool> overlaps;
  UnionFind groups = overlapGroups(f, unique, overlaps);
  std::map<std::size_t, std::vector<std::size_t>> members;
  std::vector<std::array<int, 2>> merged;
  merged.reserve(unique.size());
  for (std::size_t s = 0; s < unique.size(); ++s)
  {
    if (overlaps[s])
      members[groups.find(s)].push_back(s);
    else
      merged.push_back(unique[s]);
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
      const bool covered = std::any_of(group.begin(), group.end(), [&](std::size_t s) {
        const double t0 = param(unique[s][0]), t1 = param(unique[s][1]);
        return std::min(t0, t1) < mid && mid < std::max(t0, t1);
      });
      if (covered)
        merged.push_back({ vertices[k], vertices[k + 1] });
    }
  }
  return merged;
}

/// 4. `segments` as f's, without the points no segment uses.
void keepUsedPoints(FeatureSegments& f, std::vector<std::array<int, 2>> segments)
{
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
  mergeRepeatedPoints(f, counts);
  const std::vector<std::array<int, 2>> unique = withoutRepeatedSegments(f, counts);
  std::vector<std::array<int, 2>> merged = withOverlapsMerged(f, unique, counts);
  if (!counts.changed())
    return counts; // as given: same points, same order
  keepUsedPoints(f, std::move(merged));
  return counts;
}
}
