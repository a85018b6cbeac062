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

void TriangleSurface::validateClosed(const std::string& who) const
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
  std::unordered_map<uint64_t, int> edgeUse;
  edgeUse.reserve(triangles.size() * 2);
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
  throw InputError(msg.str());
}

double TriangleSurface::signedVolume() const
{
  double v = 0.0;
  for (const auto& t : triangles)
    v += dot(points[t[0]], cross(points[t[1]], points[t[2]]));
  return v / 6.0;
}
}
