// SPDX-License-Identifier: GPL-3.0-or-later
// Test geometry built without VTK: cubes and icospheres as triangle soups, grid sampling.
#pragma once

#include "Domain.h"
#include "HierarchicalOracle.h"
#include "TriangleSurface.h"

#include <cmath>
#include <map>

namespace omesh::test
{
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
  double volume = 0.0;
  for (const auto& f : m.triangles)
    volume += dot(m.points[f[0]], cross(m.points[f[1]], m.points[f[2]])) / 6.0;
  if (volume < 0)
    for (auto& f : m.triangles)
      std::swap(f[1], f[2]);
  return m;
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
