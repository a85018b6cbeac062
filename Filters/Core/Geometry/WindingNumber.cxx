// SPDX-License-Identifier: GPL-3.0-or-later
#include "WindingNumber.h"

#include "SeamPairs.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace omesh
{

namespace
{
constexpr int kLeafSize = 8;
/// approximate(): a node is far when its area centroid lies more than this many radii from the
/// point (Barill et al.'s beta)
constexpr double kFarRatio = 2.0;
/// The index pairs (k, l) of FarField::second's six columns.
constexpr int kPair[6][2] = { { 0, 0 }, { 1, 1 }, { 2, 2 }, { 0, 1 }, { 0, 2 }, { 1, 2 } };

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
  std::vector<FarField> far;
  far.reserve(nodes_.capacity());
  build(0, static_cast<int>(triangles_.size()), far);
  expansions_.resize(far.size());
  for (size_t i = 0; i < far.size(); ++i)
  {
    Expansion& e = expansions_[i];
    e.centre = far[i].centre;
    e.farRadius2 = kFarRatio * kFarRatio * far[i].radius * far[i].radius;
    for (int j = 0; j < 3; ++j)
      e.moments[j] = static_cast<float>(far[i].normal[j]);
    std::copy(far[i].first.begin(), far[i].first.end(), e.moments.begin() + 3);
    std::copy(far[i].second.begin(), far[i].second.end(), e.moments.begin() + 12);
  }
  const Vec3 size = nodes_[0].box.size();
  margin_ = 1e-9 * norm(size);
  indexBorder();
}

std::vector<WindingNumber::BorderItem> WindingNumber::pairedBorder() const
{
  // a directed border edge a -> b and one that runs b' -> a' close by (an unwelded crack, a
  // jittered soup's seam) pull w in nearly opposite ways: as a pair they count by their gap (see
  // gradientBound)
  const Node& root = nodes_[0];
  const std::vector<std::array<int, 2>> edges(
    borders_.begin() + root.borderFirst, borders_.begin() + root.borderFirst + root.borderCount);
  std::vector<char> paired(edges.size(), 0);
  std::vector<BorderItem> items;
  for (const SeamPair& pair : pairSeams(points_, edges, true, false))
  {
    items.push_back({ edges[pair.first], edges[pair.second], pair.gap });
    paired[pair.first] = paired[pair.second] = 1;
  }
  for (size_t e = 0; e < edges.size(); ++e)
    if (!paired[e])
      items.push_back({ edges[e] });
  return items;
}

void WindingNumber::indexBorder()
{
  if (nodes_[0].borderCount == 0)
    return;
  borderItems_ = pairedBorder();
  borderTree_.reserve(2 * borderItems_.size() / kLeafSize + 2);
  buildBorderTree(0, static_cast<int>(borderItems_.size()));
}

int WindingNumber::buildBorderTree(int first, int count)
{
  const int index = static_cast<int>(borderTree_.size());
  borderTree_.emplace_back();
  BorderNode node;
  node.first = first;
  node.count = count;
  for (int i = first; i < first + count; ++i)
  {
    const BorderItem& item = borderItems_[i];
    const double length = norm(points_[item.edge[1]] - points_[item.edge[0]]);
    node.box.add(points_[item.edge[0]]);
    node.box.add(points_[item.edge[1]]);
    if (item.partner[0] < 0)
    {
      node.length += length;
      continue;
    }
    node.box.add(points_[item.partner[0]]);
    node.box.add(points_[item.partner[1]]);
    node.gap += item.gap;
    node.gapLength += item.gap * std::max(length, norm(points_[item.partner[1]] - points_[item.partner[0]]));
  }
  if (count > kLeafSize)
  {
    // split at the median midpoint along the box's longest axis
    const Vec3 size = node.box.size();
    const int axis = size.x >= size.y && size.x >= size.z ? 0 : (size.y >= size.z ? 1 : 2);
    auto mid = [&](const BorderItem& item) { return points_[item.edge[0]][axis] + points_[item.edge[1]][axis]; };
    std::nth_element(borderItems_.begin() + first, borderItems_.begin() + first + count / 2,
      borderItems_.begin() + first + count, [&](const BorderItem& x, const BorderItem& y) { return mid(x) < mid(y); });
    node.child[0] = buildBorderTree(first, count / 2);
    node.child[1] = buildBorderTree(first + count / 2, count - count / 2);
  }
  borderTree_[index] = node;
  return index;
}

double WindingNumber::gradientBound(const BoundingBox& region) const
{
  if (borderTree_.empty())
    return 0.0;
  return borderBound(0, region, 0.5 * (region.min + region.max), 0.5 * norm(region.size())) / (4.0 * M_PI);
}

double WindingNumber::borderBound(int index, const BoundingBox& region, const Vec3& centre, double reach) const
{
  // a pair (a -> b, b' -> a', ends at most eps apart, the longer of length L) pulls at distance r
  // by at most 2 eps / r^2 + 2 L eps / r^3: the difference of its two line integrals of
  // dl x y / |y|^3 is the integral of d(dl) x K plus dl x dK, |d(dl)| <= 2 eps, |K| <= 1 / r^2,
  // |grad K| <= 2 / r^3 (K(y) = y / |y|^3; r measured to the pair's hull)
  const BorderNode& node = borderTree_[index];
  double d2 = 0.0;
  for (int a = 0; a < 3; ++a)
  {
    const double gap = std::max({ node.box.min[a] - region.max[a], region.min[a] - node.box.max[a], 0.0 });
    d2 += gap * gap;
  }
  if (d2 > dot(node.box.size(), node.box.size()))
    return (node.length + 2.0 * node.gap) / d2 + 2.0 * node.gapLength / (d2 * std::sqrt(d2)); // far: as a whole
  if (node.child[0] >= 0)
  {
    const double left = borderBound(node.child[0], region, centre, reach);
    return std::isfinite(left) ? left + borderBound(node.child[1], region, centre, reach) : left;
  }
  // a leaf near the region: item by item, from the region's centre less its half diagonal
  auto distance = [&](const std::array<int, 2>& e) {
    const Vec3& a = points_[e[0]];
    const Vec3 ab = points_[e[1]] - a;
    const double along = std::clamp(dot(centre - a, ab) / std::max(dot(ab, ab), 1e-300), 0.0, 1.0);
    return norm(centre - (a + along * ab));
  };
  double bound = 0.0;
  for (int i = node.first; i < node.first + node.count; ++i)
  {
    const BorderItem& item = borderItems_[i];
    const double length = norm(points_[item.edge[1]] - points_[item.edge[0]]);
    if (item.partner[0] < 0)
    {
      const double gap = distance(item.edge) - reach;
      if (!(gap > 0.0))
        return std::numeric_limits<double>::infinity();
      bound += length / (gap * gap);
      continue;
    }
    const double r = std::min(distance(item.edge), distance(item.partner)) - item.gap - reach;
    if (!(r > 0.0))
      return std::numeric_limits<double>::infinity();
    const double longest = std::max(length, norm(points_[item.partner[1]] - points_[item.partner[0]]));
    bound += 2.0 * item.gap / (r * r) + 2.0 * longest * item.gap / (r * r * r);
  }
  return bound;
}

int WindingNumber::build(int first, int count, std::vector<FarField>& far)
{
  const int index = static_cast<int>(nodes_.size());
  nodes_.emplace_back();
  far.emplace_back();
  {
    Node& n = nodes_.back();
    n.first = first;
    n.count = count;
    for (int t = first; t < first + count; ++t)
      for (int v : triangles_[t])
        n.box.add(points_[v]);
    n.centre = 0.5 * (n.box.min + n.box.max);
  }
  std::vector<std::array<int, 2>> edges;
  if (count <= kLeafSize)
  {
    for (int t = first; t < first + count; ++t)
      for (int e = 0; e < 3; ++e)
        edges.push_back({ triangles_[t][e], triangles_[t][(e + 1) % 3] });
    setBorder(index, edges);
    buildFarField(nodes_[index], far[index]);
    return index;
  }
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
  const int left = build(first, half, far);
  const int right = build(first + half, count - half, far);
  nodes_[index].child[0] = left;
  nodes_[index].child[1] = right;
  // the node's border is its children's, less the edges one runs opposite to the other
  for (int child : { left, right })
    edges.insert(edges.end(), borders_.begin() + nodes_[child].borderFirst,
      borders_.begin() + nodes_[child].borderFirst + nodes_[child].borderCount);
  setBorder(index, edges);
  far[index] = mergedFarField(far[left], far[right], nodes_[index].centre);
  return index;
}

void WindingNumber::setBorder(int index, std::vector<std::array<int, 2>>& edges)
{
  // directed edges that no other edge runs the opposite way: per undirected edge, the count one
  // way less the count the other way, in the direction that is left over
  std::sort(edges.begin(), edges.end(), [](const std::array<int, 2>& a, const std::array<int, 2>& b) {
    return std::minmax(a[0], a[1]) < std::minmax(b[0], b[1]);
  });
  nodes_[index].borderFirst = static_cast<int>(borders_.size());
  for (size_t i = 0; i < edges.size();)
  {
    const auto key = std::minmax(edges[i][0], edges[i][1]);
    int net = 0;
    for (; i < edges.size() && std::minmax(edges[i][0], edges[i][1]) == key; ++i)
      net += edges[i][0] < edges[i][1] ? 1 : -1;
    for (int k = 0; k < std::abs(net); ++k)
      borders_.push_back(net > 0 ? std::array<int, 2>{ key.first, key.second } : std::array<int, 2>{ key.second, key.first });
  }
  nodes_[index].borderCount = static_cast<int>(borders_.size()) - nodes_[index].borderFirst;
}

void WindingNumber::buildFarField(const Node& node, FarField& f) const
{
  Vec3 weighted{ 0, 0, 0 };
  for (int t = node.first; t < node.first + node.count; ++t)
  {
    const Vec3 &a = points_[triangles_[t][0]], &b = points_[triangles_[t][1]], &c = points_[triangles_[t][2]];
    const double area = 0.5 * norm(cross(b - a, c - a));
    f.area += area;
    weighted = weighted + (area / 3.0) * (a + b + c);
  }
  f.centre = f.area > 0.0 ? (1.0 / f.area) * weighted : node.centre;
  f.normal = { 0, 0, 0 };
  for (int t = node.first; t < node.first + node.count; ++t)
  {
    const Vec3 v[3] = { points_[triangles_[t][0]] - f.centre, points_[triangles_[t][1]] - f.centre,
      points_[triangles_[t][2]] - f.centre };
    const Vec3 vectorArea = 0.5 * cross(v[1] - v[0], v[2] - v[0]); // n dA over the triangle
    const Vec3 sum = v[0] + v[1] + v[2];
    f.normal = f.normal + vectorArea;
    for (const Vec3& corner : v)
      f.radius = std::max(f.radius, norm(corner));
    for (int j = 0; j < 3; ++j)
    {
      for (int k = 0; k < 3; ++k)
        f.first[3 * j + k] += vectorArea[j] * sum[k] / 3.0;
      // the integral of s_k s_l over a triangle with corners v (about any origin): area / 12 *
      // (sum of v_k v_l over the corners + their sums' product)
      for (int kl = 0; kl < 6; ++kl)
      {
        const int k = kPair[kl][0], l = kPair[kl][1];
        const double corners = v[0][k] * v[0][l] + v[1][k] * v[1][l] + v[2][k] * v[2][l];
        f.second[6 * j + kl] += vectorArea[j] * (corners + sum[k] * sum[l]) / 12.0;
      }
    }
  }
}

WindingNumber::FarField WindingNumber::mergedFarField(const FarField& a, const FarField& b, const Vec3& boxCentre)
{
  FarField f;
  f.area = a.area + b.area;
  f.centre = f.area > 0.0 ? (1.0 / f.area) * (a.area * a.centre + b.area * b.centre) : boxCentre;
  f.normal = a.normal + b.normal;
  for (const FarField* child : { &a, &b })
  {
    // moments about the child's centroid moved to the node's: s = s_child + delta
    const Vec3 delta = child->centre - f.centre;
    f.radius = std::max(f.radius, child->radius + norm(delta)); // a ball holding the child's ball
    for (int j = 0; j < 3; ++j)
    {
      for (int k = 0; k < 3; ++k)
        f.first[3 * j + k] += child->first[3 * j + k] + child->normal[j] * delta[k];
      for (int kl = 0; kl < 6; ++kl)
      {
        const int k = kPair[kl][0], l = kPair[kl][1];
        f.second[6 * j + kl] += child->second[6 * j + kl] + child->first[3 * j + k] * delta[l] +
          child->first[3 * j + l] * delta[k] + child->normal[j] * delta[k] * delta[l];
      }
    }
  }
  return f;
}

double WindingNumber::approximate(int index, const Vec3& p) const
{
  const Expansion& f = expansions_[index];
  const Vec3 y = f.centre - p;
  const double d2 = dot(y, y);
  if (d2 > f.farRadius2)
  {
    // the solid angle is the integral of n . G(x - p) dA, G(y) = y / |y|^3, with G expanded about
    // y = centre - p to second order in s = x - centre
    const double inv2 = 1.0 / d2, inv3 = inv2 / std::sqrt(d2), inv5 = inv3 * inv2, inv7 = inv5 * inv2;
    const float* normal = f.moments.data();
    const float* m1 = normal + 3; // [j][k]
    double yM1y = 0.0, a1 = 0.0, a3 = 0.0, a4 = 0.0;
    for (int j = 0; j < 3; ++j)
    {
      const float* s = m1 + 9 + 6 * j; // [j][kl], kl = xx yy zz xy xz yz
      const double jl[3] = { j == 0 ? s[0] : (j == 1 ? s[3] : s[4]), j == 0 ? s[3] : (j == 1 ? s[1] : s[5]),
        j == 0 ? s[4] : (j == 1 ? s[5] : s[2]) }; // [j][j l], l = x y z
      yM1y += y[j] * (m1[3 * j] * y.x + m1[3 * j + 1] * y.y + m1[3 * j + 2] * y.z);
      a1 += jl[0] * y.x + jl[1] * y.y + jl[2] * y.z;
      a3 += y[j] * (static_cast<double>(s[0]) + s[1] + s[2]);
      a4 += y[j] * (s[0] * y.x * y.x + s[1] * y.y * y.y + s[2] * y.z * y.z +
                     2.0 * (s[3] * y.x * y.y + s[4] * y.x * y.z + s[5] * y.y * y.z));
    }
    const double order0 = (normal[0] * y.x + normal[1] * y.y + normal[2] * y.z) * inv3;
    const double order1 = (static_cast<double>(m1[0]) + m1[4] + m1[8]) * inv3 - 3.0 * yM1y * inv5; // dG/dy: I/d^3 - 3 y y^T/d^5
    const double order2 = 0.5 * (-3.0 * (2.0 * a1 + a3) * inv5 + 15.0 * a4 * inv7);
    return order0 + order1 + order2;
  }
  const Node& n = nodes_[index];
  if (n.child[0] < 0 || (n.borderCount == 0 && strictlyOutside(n.box, p, margin_)))
    return evaluate(index, p); // a leaf's triangles; or closed and not around p: 0
  __builtin_prefetch(&expansions_[n.child[1]]); // (the left child follows its parent in memory)
  return approximate(n.child[0], p) + approximate(n.child[1], p);
}

double WindingNumber::approximate(const Vec3& p) const
{
  return nodes_.empty() ? 0.0 : approximate(0, p) / (4.0 * M_PI);
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
