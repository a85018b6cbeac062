// SPDX-License-Identifier: GPL-3.0-or-later
#include "AffineMap.h"

#include "InputError.h"

#include <cmath>

namespace omesh
{
AffineMap::AffineMap()
  : m_{ 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0 }
{
}

AffineMap::AffineMap(const std::array<double, 12>& rowMajor3x4)
  : m_(rowMajor3x4)
{
}

AffineMap AffineMap::scaleTranslate(const Vec3& s, const Vec3& t)
{
  return AffineMap({ s.x, 0, 0, t.x, 0, s.y, 0, t.y, 0, 0, s.z, t.z });
}

AffineMap AffineMap::inverse() const
{
  const auto& a = m_;
  for (double v : a)
    if (!std::isfinite(v))
      throw InputError("transform has a NaN or infinite entry");
  // cofactors of the 3x3 linear part
  const double c00 = a[5] * a[10] - a[6] * a[9];
  const double c01 = a[6] * a[8] - a[4] * a[10];
  const double c02 = a[4] * a[9] - a[5] * a[8];
  const double det = a[0] * c00 + a[1] * c01 + a[2] * c02;
  double scale = 0.0;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      scale = std::max(scale, std::abs(a[4 * r + c]));
  if (!std::isfinite(det) || scale == 0.0 || std::abs(det) <= 1e-14 * scale * scale * scale)
  {
    throw InputError("transform is singular (its linear part has determinant " +
      std::to_string(det) + ")");
  }
  const double id = 1.0 / det;
  std::array<double, 12> r{};
  r[0] = c00 * id;
  r[1] = (a[2] * a[9] - a[1] * a[10]) * id;
  r[2] = (a[1] * a[6] - a[2] * a[5]) * id;
  r[4] = c01 * id;
  r[5] = (a[0] * a[10] - a[2] * a[8]) * id;
  r[6] = (a[2] * a[4] - a[0] * a[6]) * id;
  r[8] = c02 * id;
  r[9] = (a[1] * a[8] - a[0] * a[9]) * id;
  r[10] = (a[0] * a[5] - a[1] * a[4]) * id;
  for (int row = 0; row < 3; ++row)
  {
    r[4 * row + 3] = -(r[4 * row] * a[3] + r[4 * row + 1] * a[7] + r[4 * row + 2] * a[11]);
  }
  for (double v : r)
    if (!std::isfinite(v))
      throw InputError("transform cannot be inverted in double precision (an entry of its inverse overflows)");
  return AffineMap(r);
}

AffineMap AffineMap::compose(const AffineMap& first) const
{
  const auto& a = m_;
  const auto& b = first.m_;
  std::array<double, 12> r{};
  for (int row = 0; row < 3; ++row)
  {
    for (int col = 0; col < 4; ++col)
    {
      double v = (col == 3) ? a[4 * row + 3] : 0.0;
      for (int k = 0; k < 3; ++k)
        v += a[4 * row + k] * b[4 * k + col];
      r[4 * row + col] = v;
    }
  }
  return AffineMap(r);
}

bool AffineMap::isIdentity() const
{
  return m_ == AffineMap().m_;
}

BoundingBox AffineMap::inverseImageOf(const BoundingBox& local) const
{
  BoundingBox world;
  if (local.empty())
    return world;
  const AffineMap inv = inverse();
  for (int corner = 0; corner < 8; ++corner)
  {
    const Vec3 p{ (corner & 1) ? local.max.x : local.min.x, (corner & 2) ? local.max.y : local.min.y,
      (corner & 4) ? local.max.z : local.min.z };
    world.add(inv.apply(p));
  }
  return world;
}
}
