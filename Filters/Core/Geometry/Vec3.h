// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <algorithm>
#include <cmath>

namespace omesh
{
/// Plain 3D vector of doubles: the only geometric value type the core's public headers use
/// (keeps CGAL out of everything that includes them, notably the VTK wrappers).
struct Vec3
{
  double x = 0.0, y = 0.0, z = 0.0;

  constexpr Vec3() = default;
  constexpr Vec3(double ax, double ay, double az)
    : x(ax)
    , y(ay)
    , z(az)
  {
  }
  double operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
  double& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }
};

inline Vec3 operator+(const Vec3& a, const Vec3& b) { return { a.x + b.x, a.y + b.y, a.z + b.z }; }
inline Vec3 operator-(const Vec3& a, const Vec3& b) { return { a.x - b.x, a.y - b.y, a.z - b.z }; }
inline Vec3 operator*(double s, const Vec3& a) { return { s * a.x, s * a.y, s * a.z }; }
inline double dot(const Vec3& a, const Vec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline Vec3 cross(const Vec3& a, const Vec3& b)
{
  return { a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x };
}
inline double norm(const Vec3& a) { return std::sqrt(dot(a, a)); }
/// Two unit vectors u, v perpendicular to the unit vector w and to each other (u from the axis
/// least aligned with w): a ring of probes around a line.
inline void perpendicularPair(const Vec3& w, Vec3& u, Vec3& v)
{
  Vec3 e{ 0, 0, 0 };
  const double ax = std::abs(w.x), ay = std::abs(w.y), az = std::abs(w.z);
  e[ax <= ay && ax <= az ? 0 : ay <= az ? 1 : 2] = 1.0;
  u = cross(w, e);
  u = (1.0 / norm(u)) * u;
  v = cross(w, u);
}
inline bool isFinite(const Vec3& a)
{
  return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z);
}
/// Point on segment ab at parameter t, computed from the nearer end (stays accurate near b when
/// a is far away).
inline Vec3 lerp(const Vec3& a, const Vec3& b, double t)
{
  return t <= 0.5 ? a + t * (b - a) : b + (1.0 - t) * (a - b);
}
/// Parameter in [0, 1] of the point of segment ab nearest to p (0 for a degenerate segment).
inline double segmentParameter(const Vec3& p, const Vec3& a, const Vec3& b)
{
  const Vec3 d = b - a;
  const double dd = dot(d, d);
  return dd > 0 ? std::clamp(dot(p - a, d) / dd, 0.0, 1.0) : 0.0;
}
/// Distance from p to segment ab.
inline double distanceToSegment(const Vec3& p, const Vec3& a, const Vec3& b)
{
  return norm(p - (a + segmentParameter(p, a, b) * (b - a)));
}
}
