// SPDX-License-Identifier: GPL-3.0-or-later
// Test geometry built without VTK: cubes and icospheres as triangle soups, grid sampling.
#pragma once

#include "Domain.h"
#include "FeatureSegments.h"
#include "HierarchicalOracle.h"
#include "TriangleSurface.h"

#include <array>
#include <cmath>
#include <map>
#include <random>
#include <utility>
#include <vector>

namespace omesh::test
{
/// The polyline through `points`, one segment per pair of consecutive points.
inline FeatureSegments polyline(const std::vector<Vec3>& points)
{
  FeatureSegments f;
  f.points = points;
  for (int i = 0; i + 1 < static_cast<int>(points.size()); ++i)
    f.segments.push_back({ i, i + 1 });
  return f;
}

/// The 12 edges of the cube [lo, hi]^3 as feature segments (its 8 corners as points).
inline FeatureSegments cubeEdges(double lo, double hi)
{
  FeatureSegments f;
  for (int i = 0; i < 8; ++i)
    f.points.push_back({ (i & 1) ? hi : lo, (i & 2) ? hi : lo, (i & 4) ? hi : lo });
  for (int i = 0; i < 8; ++i)
    for (int bit : { 1, 2, 4 })
      if (!(i & bit))
        f.segments.push_back({ i, i | bit });
  return f;
}

/// Axis-aligned cube [lo, hi]^3, 12 outward triangles.
inline TriangleSurface cube(double lo, double hi)
{
  TriangleSurface s;
  for (int i = 0; i < 8; ++i)
    s.points.push_back({ (i & 1) ? hi : lo, (i & 2) ? hi : lo, (i & 4) ? hi : lo });
  s.triangles = { { 0, 2, 1 }, { 1, 2, 3 }, { 4, 5, 6 }, { 5, 7, 6 }, { 0, 1, 4 }, { 1, 5, 4 },
    { 2, 6, 3 }, { 3, 6, 7 }, { 0, 4, 2 }, { 2, 4, 6 }, { 1, 3, 5 }, { 3, 7, 5 } };
  return s;
}

/// Flips every triangle when the signed volume is negative: the triangles then face outwards.
inline void orientOutward(TriangleSurface& m)
{
  double volume = 0.0;
  for (const auto& f : m.triangles)
    volume += dot(m.points[f[0]], cross(m.points[f[1]], m.points[f[2]])) / 6.0;
  if (volume < 0)
    for (auto& f : m.triangles)
      std::swap(f[1], f[2]);
}

/// An L-shaped prism (profile (0,0) (3,0) (3,1) (1,1) (1,2) (0,2) in x-z, extruded along y over
/// [0, 1]), scaled by `s` and moved by `t`: its bounding-box centre lies on its flat face z = 1,
/// inside it (a CAD part that once seeded micro-tetrahedron clusters). Outward triangles. The
/// coordinates are rounded to float, as a .vtp/.stl stores them: the centre then lies within
/// rounding of the face, not exactly on it.
inline TriangleSurface lPrism(double s, const Vec3& t)
{
  const double xz[6][2] = { { 0, 0 }, { 3, 0 }, { 3, 1 }, { 1, 1 }, { 1, 2 }, { 0, 2 } };
  TriangleSurface m;
  for (int y = 0; y < 2; ++y)
    for (const auto& p : xz)
    {
      const Vec3 q = t + s * Vec3{ p[0], double(y), p[1] };
      m.points.push_back({ double(float(q.x)), double(float(q.y)), double(float(q.z)) });
    }
  for (int off : { 0, 6 }) // caps: two convex quads each
    for (const auto& q : { std::array<int, 4>{ 0, 1, 2, 3 }, std::array<int, 4>{ 0, 3, 4, 5 } })
    {
      m.triangles.push_back({ off + q[0], off + q[1], off + q[2] });
      m.triangles.push_back({ off + q[0], off + q[2], off + q[3] });
    }
  for (int i = 0; i < 6; ++i)
  {
    const int j = (i + 1) % 6;
    m.triangles.push_back({ i, 6 + j, j });
    m.triangles.push_back({ i, 6 + i, 6 + j });
  }
  // the y = 0 cap points -y ((x, z) counter-clockwise), the y = 1 cap must point +y
  for (size_t f = 4; f < 8; ++f)
    std::swap(m.triangles[f][1], m.triangles[f][2]); // y = 1 cap points +y
  orientOutward(m);
  return m;
}

/// Every triangle its own three points (an unwelded soup, as STL files are), moved at random by up
/// to `jitter` per coordinate.
inline TriangleSurface soupOf(const TriangleSurface& s, double jitter, unsigned seed)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-jitter, jitter);
  TriangleSurface soup;
  for (const auto& t : s.triangles)
  {
    const int first = static_cast<int>(soup.points.size());
    for (int v : t)
      soup.points.push_back(s.points[v] + Vec3{ u(rng), u(rng), u(rng) });
    soup.triangles.push_back({ first, first + 1, first + 2 });
  }
  return soup;
}

/// Subdivided octahedron projected to a sphere (a closed polyhedron with many degenerate-ray cases).
inline TriangleSurface icosphere(const Vec3& c, double r, int levels)
{
  TriangleSurface s;
  s.points = { { 1, 0, 0 }, { -1, 0, 0 }, { 0, 1, 0 }, { 0, -1, 0 }, { 0, 0, 1 }, { 0, 0, -1 } };
  s.triangles = { { 0, 2, 4 }, { 2, 1, 4 }, { 1, 3, 4 }, { 3, 0, 4 }, { 2, 0, 5 }, { 1, 2, 5 },
    { 3, 1, 5 }, { 0, 3, 5 } };
  for (int l = 0; l < levels; ++l)
  {
    std::map<std::pair<int, int>, int> mid;
    auto midpoint = [&](int a, int b) {
      auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end())
        return it->second;
      Vec3 m = 0.5 * (s.points[a] + s.points[b]);
      m = (1.0 / norm(m)) * m;
      s.points.push_back(m);
      return mid[key] = static_cast<int>(s.points.size()) - 1;
    };
    std::vector<std::array<int, 3>> next;
    for (const auto& t : s.triangles)
    {
      const int ab = midpoint(t[0], t[1]), bc = midpoint(t[1], t[2]), ca = midpoint(t[2], t[0]);
      next.push_back({ t[0], ab, ca });
      next.push_back({ ab, t[1], bc });
      next.push_back({ ca, bc, t[2] });
      next.push_back({ ab, bc, ca });
    }
    s.triangles.swap(next);
  }
  for (auto& p : s.points)
    p = c + r * p;
  return s;
}

/// Closed solid through axis-aligned rectangles (half sizes x, y at height z, bottom to top), as
/// oraclemesh_cases.cases lofts its implants: planar quads, so every face is flat; two rectangles at one
/// height make a flat annulus (a collar's underside, with concave edges where the stem meets it).
inline TriangleSurface loftedRectangles(const std::vector<std::pair<std::array<double, 2>, double>>& rects)
{
  TriangleSurface s;
  for (const auto& [half, z] : rects)
    for (const auto& [sx, sy] : { std::pair{ -1, -1 }, { 1, -1 }, { 1, 1 }, { -1, 1 } })
      s.points.push_back({ sx * half[0], sy * half[1], z });
  const int top = 4 * (static_cast<int>(rects.size()) - 1);
  for (int lo = 0; lo < top; lo += 4)
    for (int i = 0; i < 4; ++i)
    {
      const int j = (i + 1) % 4;
      s.triangles.push_back({ lo + i, lo + j, lo + 4 + j });
      s.triangles.push_back({ lo + i, lo + 4 + j, lo + 4 + i });
    }
  s.triangles.insert(s.triangles.end(), { { 0, 2, 1 }, { 0, 3, 2 }, { top, top + 1, top + 2 }, { top, top + 2, top + 3 } });
  return s;
}

/// The unit cube [0, 1]^3 with its edge x = y = 1 chamfered, `c` cut from each face: the chamfer's
/// two edges are 135-degree dihedrals (normals 45 degrees apart), all other edges 90-degree ones.
/// Pentagon caps at z = 0 and 1 (fans), outward triangles.
inline TriangleSurface chamferedCube(double c)
{
  TriangleSurface s;
  for (double z : { 0.0, 1.0 })
    for (const auto& [x, y] : { std::pair{ 0.0, 0.0 }, { 1.0, 0.0 }, { 1.0, 1.0 - c }, { 1.0 - c, 1.0 }, { 0.0, 1.0 } })
      s.points.push_back({ x, y, z });
  for (int i = 0; i < 5; ++i) // sides, the pentagon counter-clockwise seen from +z
  {
    const int j = (i + 1) % 5;
    s.triangles.push_back({ i, j, j + 5 });
    s.triangles.push_back({ i, j + 5, i + 5 });
  }
  for (int i = 1; i < 4; ++i)
  {
    s.triangles.push_back({ 0, i + 1, i });
    s.triangles.push_back({ 5, 5 + i, 6 + i });
  }
  return s;
}

/// `s` turned by the unit quaternion (w, x, y, z).
inline TriangleSurface rotated(TriangleSurface s, const std::array<double, 4>& q)
{
  const double w = q[0], x = q[1], y = q[2], z = q[3];
  const double r[3][3] = { { 1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w) },
    { 2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w) },
    { 2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y) } };
  for (Vec3& p : s.points)
    p = { r[0][0] * p.x + r[0][1] * p.y + r[0][2] * p.z, r[1][0] * p.x + r[1][1] * p.y + r[1][2] * p.z,
      r[2][0] * p.x + r[2][1] * p.y + r[2][2] * p.z };
  return s;
}

/// Edges of a closed surface whose two triangles' normals differ by more than `angle` degrees (as
/// vtkFeatureEdges with that feature angle).
inline FeatureSegments sharpEdges(const TriangleSurface& s, double angle)
{
  std::map<std::pair<int, int>, std::vector<Vec3>> normals;
  for (const auto& t : s.triangles)
  {
    const Vec3 u = s.points[t[1]] - s.points[t[0]], v = s.points[t[2]] - s.points[t[0]];
    const Vec3 n{ u.y * v.z - u.z * v.y, u.z * v.x - u.x * v.z, u.x * v.y - u.y * v.x };
    for (int i = 0; i < 3; ++i)
      normals[std::minmax(t[i], t[(i + 1) % 3])].push_back((1.0 / norm(n)) * n);
  }
  FeatureSegments f;
  f.points = s.points;
  for (const auto& [edge, n] : normals)
    if (n.size() == 2 && dot(n[0], n[1]) < std::cos(angle * M_PI / 180.0))
      f.segments.push_back({ edge.first, edge.second });
  return f;
}

/// Volume per material of `f` sampled at the centres of an n^3 grid over `box`.
template <typename F>
std::map<int, double> sampledVolumes(const F& materialOf, const BoundingBox& box, int n)
{
  std::map<int, double> v;
  const Vec3 size = box.size();
  const double cell = size.x * size.y * size.z / (double(n) * n * n);
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
      {
        const Vec3 p{ box.min.x + (i + 0.5) * size.x / n, box.min.y + (j + 0.5) * size.y / n,
          box.min.z + (k + 0.5) * size.z / n };
        const int m = materialOf(p);
        if (m != kOutside)
          v[m] += cell;
      }
  return v;
}

inline BoundingBox makeBox(const Vec3& lo, const Vec3& hi)
{
  BoundingBox b;
  b.add(lo);
  b.add(hi);
  return b;
}
}
