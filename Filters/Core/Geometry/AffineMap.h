// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include "BoundingBox.h"
#include "Vec3.h"

#include <array>

namespace omesh
{
/// x' = A x + t, stored as 3 rows of [A | t]. Shapes and label maps use one to go from world to
/// their own frame (VTK implicit-function transforms, image direction matrices). An affine map keeps
/// the parameter of a point along a segment, so crossings computed in the local frame hold in the
/// world frame too.
class AffineMap
{
public:
  AffineMap(); ///< identity
  explicit AffineMap(const std::array<double, 12>& rowMajor3x4);

  static AffineMap scaleTranslate(const Vec3& scale, const Vec3& translate);

  Vec3 apply(const Vec3& p) const
  {
    return { m_[0] * p.x + m_[1] * p.y + m_[2] * p.z + m_[3],
      m_[4] * p.x + m_[5] * p.y + m_[6] * p.z + m_[7],
      m_[8] * p.x + m_[9] * p.y + m_[10] * p.z + m_[11] };
  }
  /// Throws InputError when the linear part is singular (or not finite).
  AffineMap inverse() const;
  AffineMap compose(const AffineMap& first) const; ///< this o first
  bool isIdentity() const;
  const std::array<double, 12>& rows() const { return m_; }
  /// World box of the image of a local box under this map's inverse (for bounds of local shapes).
  BoundingBox inverseImageOf(const BoundingBox& local) const;

private:
  std::array<double, 12> m_;
};
}
