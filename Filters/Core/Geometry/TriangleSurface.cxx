// SPDX-License-Identifier: GPL-3.0-or-later
#include "TriangleSurface.h"

#include "InputError.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <unordered_map>

namespace omesh
{
namespace
{
/// Coordinates beyond this magnitude are refused: no model is that large, and squared distances
/// near it lose every significant digit (1e300 overflowed the surface's grid).
constexpr double kLargestCoordinate = 1e15;

std::string describePoint(const std::vector<Vec3>& pts, int i)
{
  std::ostringstream s;
  s << i << " (" << pts[i].x << ", " << pts[i].y << ", " << pts[i].z << ")";
  return s.str();
}
}

void TriangleSurface::validateTriangles(const std::string& who) const
{
  if (triangles.empty())
    throw InputError(who + ": surface has no triangles");
  const int n = static_cast<int>(points.size());
  for (int i = 0; i < n; ++i)
  {
    if (!isFinite(points[i]))
      throw InputError(who + ": surface point " + std::to_string(i) + " has a NaN or infinite coordinate");
    const Vec3& p = points[i];
    if (std::max({ std::abs(p.x), std::abs(p.y), std::abs(p.z) }) > kLargestCoordinate)
      throw InputError(who + ": surface point " + describePoint(points, i) +
        " has a coordinate beyond 1e15 in magnitude (absurd; check the file's units)");
  }
  for (size_t t = 0; t < triangles.size(); ++t)
  {
    const auto& tri = triangles[t];
    for (int v : tri)
    {
      if (v < 0 || v >= n)
        throw InputError(who + ": triangle " + std::to_string(t) + " refers to point " +
          std::to_string(v) + ", but the surface has " + std::to_string(n) + " points");
    }
    if (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2])
      throw InputError(who + ": triangle " + std::to_string(t) + " repeats a vertex (degenerate)");
  }
}

void TriangleSurface::validateClosed(const std::string& who) const
{
  validateTriangles(who);
  std::unordered_map<uint64_t, int> edgeUse;
  edgeUse.reserve(triangles.size() * 2);
  for (const auto& tri : triangles)
  {
    for (int e = 0; e < 3; ++e)
    {
      const auto lo = static_cast<uint64_t>(std::min(tri[e], tri[(e + 1) % 3]));
      const auto hi = static_cast<uint64_t>(std::max(tri[e], tri[(e + 1) % 3]));
      ++edgeUse[(lo << 32) | hi];
    }
  }
  std::vector<std::pair<uint64_t, int>> bad;
  for (const auto& [key, uses] : edgeUse)
  {
    if (uses != 2)
      bad.emplace_back(key, uses);
  }
  if (bad.empty())
    return;
  std::sort(bad.begin(), bad.end());
  size_t open = 0;
  for (const auto& b : bad)
    open += (b.second == 1);
  std::ostringstream msg;
  msg << who << ": surface is not closed: " << open << " open edge(s) (used by one triangle) and "
      << bad.size() - open << " non-manifold edge(s) (used by more than two); first:";
  for (size_t i = 0; i < std::min<size_t>(bad.size(), 5); ++i)
  {
    const int a = static_cast<int>(bad[i].first >> 32);
    const int b = static_cast<int>(bad[i].first & 0xffffffffu);
    msg << (i ? ";" : "") << " edge " << describePoint(points, a) << " - " << describePoint(points, b)
        << " used by " << bad[i].second << " triangle(s)";
  }
  if (open > 0)
    msg << "; " << describeHoles(borderLoops())
        << " (the winding-number inside test, InsideTest WindingNumber, meshes surfaces with holes)";
  throw InputError(msg.str());
}

std::vector<std::array<int, 2>> TriangleSurface::borderEdges() const
{
  // undirected edge -> number of triangles using it
  std::unordered_map<uint64_t, int> edgeUse;
  edgeUse.reserve(triangles.size() * 2);
  auto key = [](int a, int b) {
    return (static_cast<uint64_t>(std::min(a, b)) << 32) | static_cast<uint64_t>(std::max(a, b));
  };
  for (const auto& tri : triangles)
    for (int e = 0; e < 3; ++e)
      ++edgeUse[key(tri[e], tri[(e + 1) % 3])];
  std::vector<std::array<int, 2>> border;
  for (const auto& [k, uses] : edgeUse)
    if (uses == 1)
      border.push_back({ static_cast<int>(k >> 32), static_cast<int>(k & 0xffffffffu) });
  std::sort(border.begin(), border.end()); // deterministic order
  return border;
}

std::vector<BorderLoop> TriangleSurface::borderLoops() const
{
  const std::vector<std::array<int, 2>> border = borderEdges();
  std::unordered_map<int, std::vector<size_t>> at; // vertex -> border edges
  for (size_t e = 0; e < border.size(); ++e)
  {
    at[border[e][0]].push_back(e);
    at[border[e][1]].push_back(e);
  }
  std::vector<char> used(border.size(), 0);
  std::vector<BorderLoop> loops;
  for (size_t start = 0; start < border.size(); ++start)
  {
    if (used[start])
      continue;
    BorderLoop loop;
    Vec3 weighted;
    const int first = border[start][0];
    int current = first;
    size_t e = start;
    while (true)
    {
      used[e] = 1;
      const Vec3& a = points[border[e][0]];
      const Vec3& b = points[border[e][1]];
      const double len = norm(b - a);
      ++loop.edges;
      loop.length += len;
      weighted = weighted + (0.5 * len) * (a + b);
      current = border[e][0] == current ? border[e][1] : border[e][0];
      if (current == first)
        break;
      size_t next = border.size();
      for (size_t candidate : at[current])
        if (!used[candidate])
        {
          next = candidate;
          break;
        }
      if (next == border.size())
      {
        loop.closed = false;
        break;
      }
      e = next;
    }
    loop.centre = loop.length > 0 ? (1.0 / loop.length) * weighted : points[first];
    loops.push_back(loop);
  }
  std::stable_sort(loops.begin(), loops.end(), [](const BorderLoop& x, const BorderLoop& y) { return x.length > y.length; });
  return loops;
}

std::string TriangleSurface::describeHoles(const std::vector<BorderLoop>& loops)
{
  std::ostringstream o;
  o << loops.size() << " hole(s) (border loops):";
  for (size_t i = 0; i < std::min<size_t>(loops.size(), 5); ++i)
  {
    const BorderLoop& l = loops[i];
    o << (i ? ";" : "") << " " << l.edges << " edge(s), length " << l.length << " around (" << l.centre.x << ", "
      << l.centre.y << ", " << l.centre.z << ")" << (l.closed ? "" : " (not closed)");
  }
  if (loops.size() > 5)
    o << "; ...";
  return o.str();
}

BoundingBox TriangleSurface::bounds() const
{
  BoundingBox box;
  for (const Vec3& p : points)
    box.add(p);
  return box;
}

double TriangleSurface::signedVolume() const
{
  double v = 0.0;
  for (const auto& t : triangles)
    v += dot(points[t[0]], cross(points[t[1]], points[t[2]]));
  return v / 6.0;
}
}
