// SPDX-License-Identifier: GPL-3.0-or-later
#include "WindingNumber.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

namespace omesh
{

namespace
{
constexpr int kLeafSize = 8;

/// Signed solid angle of triangle abc seen from p (Van Oosterom & Strackee's formula).
double solidAngle(const Vec3& p, const Vec3& a0, const Vec3& b0, const Vec3& c0)
{
  const Vec3 a = a0 - p, b = b0 - p, c = c0 - p;
  const double la = norm(a), lb = norm(b), lc = norm(c);
  const double det = dot(a, cross(b, c));
  const double den = la * lb * lc + dot(a, b) * lc + dot(b, c) * la + dot(c, a) * lb;
  return 2.0 * std::atan2(det, den);
}

bool strictlyOutside(const BoundingBox& b, const Vec3& p, double margin)
{
  return p.x < b.min.x - margin || p.y < b.min.y - margin || p.z < b.min.z - margin || p.x > b.max.x + margin ||
    p.y > b.max.y + margin || p.z > b.max.z + margin;
}
}

WindingNumber::WindingNumber(const std::vector<Vec3>& points, const std::vector<std::array<int, 3>>& triangles)
  : points_(points)
  , triangles_(triangles)
{
  if (triangles_.empty())
    return;
  nodes_.reserve(2 * triangles_.size() / kLeafSize + 2);
  build(0, static_cast<int>(triangles_.size()));
  const Vec3 size = nodes_[0].box.size();
  margin_ = 1e-9 * norm(size);
  // the border in at most 64 groups of neighbouring edges (sorted along a grid's cells, z-major)
  const Node& root = nodes_[0];
  std::vector<std::array<int, 2>> edges(borders_.begin() + root.borderFirst, borders_.begin() + root.borderFirst + root.borderCount);
  if (edges.empty())
    return;
  const int cells = 8;
  auto cellOf = [&](const std::array<int, 2>& e) {
    const Vec3 m = 0.5 * (points_[e[0]] + points_[e[1]]);
    int key = 0;
    for (int a = 2; a >= 0; --a)
    {
      const double f = size[a] > 0 ? (m[a] - root.box.min[a]) / size[a] : 0.0;
      key = key * cells + std::clamp(static_cast<int>(f * cells), 0, cells - 1);
    }
    return key;
  };
  std::stable_sort(edges.begin(), edges.end(), [&](const auto& x, const auto& y) { return cellOf(x) < cellOf(y); });
  const size_t group = std::max<size_t>(8, (edges.size() + 63) / 64);
  for (size_t first = 0; first < edges.size(); first += group)
  {
    BorderCluster c;
    c.first = static_cast<int>(first);
    c.count = static_cast<int>(std::min(edges.size(), first + group) - first);
    for (size_t e = first; e < first + c.count; ++e)
    {
      c.box.add(points_[edges[e][0]]);
      c.box.add(points_[edges[e][1]]);
      c.length += norm(points_[edges[e][1]] - points_[edges[e][0]]);
    }
    clusters_.push_back(c);
  }
  clusterEdges_ = std::move(edges);
}

double WindingNumber::gradientBound(const BoundingBox& region) const
{
  double bound = 0.0;
  for (const BorderCluster& c : clusters_)
  {
    double d2 = 0.0;
    for (int a = 0; a < 3; ++a)
    {
      const double gap = std::max({ c.box.min[a] - region.max[a], region.min[a] - c.box.max[a], 0.0 });
      d2 += gap * gap;
    }
    if (!(d2 > 0.0))
      return std::numeric_limits<double>::infinity();
    if (d2 > dot(c.box.size(), c.box.size()) || c.count > 32)
    {
      bound += c.length / d2; // far (or many edges, as a soup's): the cluster as a whole
      continue;
    }
    // near: edge by edge, from the region's centre less its half diagonal
    const Vec3 centre = 0.5 * (region.min + region.max);
    const double reach = 0.5 * norm(region.size());
    for (int e = c.first; e < c.first + c.count; ++e)
    {
      const Vec3& a = points_[clusterEdges_[e][0]];
      const Vec3 ab = points_[clusterEdges_[e][1]] - a;
      const double along = std::clamp(dot(centre - a, ab) / std::max(dot(ab, ab), 1e-300), 0.0, 1.0);
      const double gap = norm(centre - (a + along * ab)) - reach;
      if (!(gap > 0.0))
        return std::numeric_limits<double>::infinity();
      bound += norm(ab) / (gap * gap);
    }
  }
  return bound / (4.0 * M_PI);
}

int WindingNumber::build(int first, int count)
{
  const int index = static_cast<int>(nodes_.size());
  nodes_.emplace_back();
  {
    Node& n = nodes_.back();
    n.first = first;
    n.count = count;
    for (int t = first; t < first + count; ++t)
      for (int v : triangles_[t])
        n.box.add(points_[v]);
    n.centre = 0.5 * (n.box.min + n.box.max);
  }
  // directed edges that no other triangle of the node runs the opposite way: the node's border
  std::map<std::pair<int, int>, int> directed;
  for (int t = first; t < first + count; ++t)
    for (int e = 0; e < 3; ++e)
    {
      const int a = triangles_[t][e], b = triangles_[t][(e + 1) % 3];
      auto opposite = directed.find({ b, a });
      if (opposite != directed.end() && opposite->second > 0)
      {
        if (--opposite->second == 0)
          directed.erase(opposite);
      }
      else
        ++directed[{ a, b }];
    }
  nodes_[index].borderFirst = static_cast<int>(borders_.size());
  for (const auto& [edge, times] : directed)
    for (int k = 0; k < times; ++k)
      borders_.push_back({ edge.first, edge.second });
  nodes_[index].borderCount = static_cast<int>(borders_.size()) - nodes_[index].borderFirst;
  if (count <= kLeafSize)
    return index;
  // split at the median centroid along the longest axis of the centroids' box
  BoundingBox centroids;
  auto centroid = [&](const std::array<int, 3>& t) {
    return (1.0 / 3.0) * (points_[t[0]] + points_[t[1]] + points_[t[2]]);
  };
  for (int t = first; t < first + count; ++t)
    centroids.add(centroid(triangles_[t]));
  const Vec3 size = centroids.size();
  const int axis = size.x >= size.y && size.x >= size.z ? 0 : (size.y >= size.z ? 1 : 2);
  const int half = count / 2;
  std::nth_element(triangles_.begin() + first, triangles_.begin() + first + half, triangles_.begin() + first + count,
    [&](const std::array<int, 3>& a, const std::array<int, 3>& b) { return centroid(a)[axis] < centroid(b)[axis]; });
  const int left = build(first, half);
  const int right = build(first + half, count - half);
  nodes_[index].child[0] = left;
  nodes_[index].child[1] = right;
  return index;
}

double WindingNumber::evaluate(int index, const Vec3& p) const
{
  const Node& n = nodes_[index];
  if (n.borderCount < n.count && strictlyOutside(n.box, p, margin_))
  {
    // node + fan(centre, border) is closed and lies in the box: it does not wind around p
    double sum = 0.0;
    for (int e = n.borderFirst; e < n.borderFirst + n.borderCount; ++e)
      sum += solidAngle(p, points_[borders_[e][0]], points_[borders_[e][1]], n.centre);
    return sum;
  }
  if (n.child[0] < 0)
  {
    double sum = 0.0;
    for (int t = n.first; t < n.first + n.count; ++t)
      sum += solidAngle(p, points_[triangles_[t][0]], points_[triangles_[t][1]], points_[triangles_[t][2]]);
    return sum;
  }
  return evaluate(n.child[0], p) + evaluate(n.child[1], p);
}

double WindingNumber::operator()(const Vec3& p) const
{
  if (nodes_.empty())
    return 0.0;
  return evaluate(0, p) / (4.0 * M_PI);
}

double WindingNumber::bruteForce(const Vec3& p) const
{
  double sum = 0.0;
  for (const auto& t : triangles_)
    sum += solidAngle(p, points_[t[0]], points_[t[1]], points_[t[2]]);
  return sum / (4.0 * M_PI);
}
}
