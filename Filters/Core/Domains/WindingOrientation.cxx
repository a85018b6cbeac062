// SPDX-License-Identifier: GPL-3.0-or-later
#include "WindingOrientation.h"

#include "BoundingBox.h"
#include "InputError.h"
#include "TriangleSurface.h"
#include "WindingNumber.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <sstream>
#include <unordered_map>
#include <vector>

namespace omesh
{
namespace
{
/// The root of x's tree in the union-find forest `parent` (path halving).
std::size_t rootOf(std::vector<std::size_t>& parent, std::size_t x)
{
  while (parent[x] != x)
    x = parent[x] = parent[parent[x]];
  return x;
}

/// Per component root in `parent`: whether the component is open, one of its edges used once.
std::vector<char> openComponents(const std::vector<std::array<int, 3>>& polygons, std::vector<std::size_t>& parent)
{
  auto find = [&](std::size_t x) { return rootOf(parent, x); };
  std::vector<char> open(parent.size(), 0);
  std::unordered_map<uint64_t, int> edgeUse;
  edgeUse.reserve(polygons.size() * 2);
  auto key = [](int a, int b) { return (static_cast<uint64_t>(std::min(a, b)) << 32) | static_cast<uint64_t>(std::max(a, b)); };
  for (const auto& poly : polygons)
    for (int e = 0; e < 3; ++e)
      ++edgeUse[key(poly[e], poly[(e + 1) % 3])];
  for (const auto& poly : polygons)
    for (int e = 0; e < 3; ++e)
      if (edgeUse[key(poly[e], poly[(e + 1) % 3])] == 1)
        open[find(poly[0])] = 1;
  return open;
}

/// Reverses each closed component (by root in `parent`) that lies inside an odd number of other
/// components: the inner wall of a hollow part bounds a cavity. Up to 64 components (beyond, none).
void reverseNestedComponents(const std::vector<Vec3>& points, std::vector<std::array<int, 3>>& polygons,
  const std::vector<char>& open, std::vector<std::size_t>& parent)
{
  auto find = [&](std::size_t x) { return rootOf(parent, x); };
  // nesting: component d lies inside component c if c's winding number at a vertex of d is > 1/2
  std::vector<std::size_t> roots;
  std::vector<int> componentOf(points.size(), -1);
  for (const auto& poly : polygons)
  {
    const std::size_t r = find(poly[0]);
    if (componentOf[r] < 0)
    {
      componentOf[r] = static_cast<int>(roots.size());
      roots.push_back(r);
    }
  }
  const size_t k = roots.size();
  if (k < 2 || k > 64)
    return;
  std::vector<std::vector<std::array<int, 3>>> tris(k);
  for (const auto& poly : polygons)
    tris[componentOf[find(poly[0])]].push_back(poly);
  // d is nested in c when c winds around every probe of d (up to 32 corners spread over d), so
  // components that merely overlap (allowed self-intersections) are not taken as cavities
  std::vector<std::vector<Vec3>> probes(k);
  for (size_t c = 0; c < k; ++c)
  {
    const size_t step = std::max<size_t>(1, tris[c].size() / 32);
    for (size_t t = 0; t < tris[c].size(); t += step)
      probes[c].push_back(points[tris[c][t][0]]);
  }
  std::vector<int> depth(k, 0);
  for (size_t c = 0; c < k; ++c)
  {
    const WindingNumber w(points, tris[c]);
    for (size_t d = 0; d < k; ++d)
      if (d != c && std::all_of(probes[d].begin(), probes[d].end(), [&](const Vec3& p) { return w(p) > 0.5; }))
        ++depth[d];
  }
  for (auto& poly : polygons)
    if (depth[componentOf[find(poly[0])]] % 2 == 1 && !open[find(poly[0])])
      std::reverse(poly.begin(), poly.end());
}
}

void orientComponentsForWinding(TriangleSurface& soup, const TriangleSurface& input)
{
  const std::vector<Vec3>& points = soup.points;
  std::vector<std::array<int, 3>>& polygons = soup.triangles;
  std::vector<std::size_t> parent(points.size());
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](std::size_t x) { return rootOf(parent, x); };
  for (const auto& poly : polygons)
    for (std::size_t k = 1; k < poly.size(); ++k)
      parent[find(poly[k])] = find(poly[0]);
  std::vector<BoundingBox> boxes(points.size());
  for (const auto& poly : polygons)
    for (std::size_t v : poly)
      boxes[find(poly[0])].add(points[v]);
  const std::vector<char> open = openComponents(polygons, parent);
  std::vector<double> volume(points.size(), 0.0), agreement(points.size(), 0.0);
  for (std::size_t t = 0; t < polygons.size(); ++t)
  {
    const auto& poly = polygons[t];
    const std::size_t root = find(poly[0]);
    const Vec3 c = 0.5 * (boxes[root].min + boxes[root].max);
    auto at = [&](std::size_t k) {
      const Vec3& q = points[poly[k]];
      return Vec3{ q.x - c.x, q.y - c.y, q.z - c.z };
    };
    volume[root] += dot(at(0), cross(at(1), at(2)));
    const auto& given = input.triangles[t];
    const Vec3& a = input.points[given[0]];
    agreement[root] += dot(cross(points[poly[1]] - points[poly[0]], points[poly[2]] - points[poly[0]]),
      cross(input.points[given[1]] - a, input.points[given[2]] - a));
  }
  for (auto& poly : polygons)
  {
    const std::size_t root = find(poly[0]);
    if (open[root] ? agreement[root] < 0 : volume[root] < 0)
      std::reverse(poly.begin(), poly.end());
  }
  // the open pieces together take the side that bounds a positive volume (a soup given inside out)
  BoundingBox all;
  for (const Vec3& p : points)
    all.add(p);
  const Vec3 centre = 0.5 * (all.min + all.max);
  double openVolume = 0.0;
  for (const auto& poly : polygons)
    if (open[find(poly[0])])
      openVolume += dot(points[poly[0]] - centre, cross(points[poly[1]] - centre, points[poly[2]] - centre));
  if (openVolume < 0)
    for (auto& poly : polygons)
      if (open[find(poly[0])])
        std::reverse(poly.begin(), poly.end());
  reverseNestedComponents(points, polygons, open, parent);
}

void refuseIfNoVolume(const WindingNumber& w, const TriangleSurface& soup, const std::string& who)
{
  const size_t step = std::max<size_t>(1, soup.triangles.size() / 4096);
  double highest = -1e300;
  for (size_t t = 0; t < soup.triangles.size(); t += step)
  {
    const auto& tri = soup.triangles[t];
    const Vec3 &a = soup.points[tri[0]], &b = soup.points[tri[1]], &c = soup.points[tri[2]];
    const Vec3 n = cross(b - a, c - a);
    const double area2 = norm(n);
    if (!(area2 > 0))
      continue;
    const Vec3 offset = (1e-3 * std::sqrt(0.5 * area2) / area2) * n;
    const Vec3 centre = (1.0 / 3.0) * (a + b + c);
    highest = std::max({ highest, w(centre + offset), w(centre - offset) });
    if (highest > 0.51)
      return;
  }
  std::ostringstream o;
  o << who << ": surface encloses no volume: the generalized winding number stays at or below " << std::max(highest, 0.0)
    << " next to its " << soup.triangles.size()
    << " triangle(s) (inside needs above 1/2): an open patch or a plane, not the boundary of a solid"
       " (give a cutting plane as an implicit plane domain, a patch as feature lines or a closed surface)";
  throw InputError(o.str());
}
}
