// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include "ImplicitShapeDomain.h"

#include <limits>

namespace omesh
{
/// Closed cylinder around the axis through `center`: radial distance <= radius and, when `height`
/// is finite, |axial offset from center| <= height / 2 (a capped screw). An infinite height gives
/// vtkCylinder's unbounded cylinder.
class CylinderDomain : public ImplicitShapeDomain
{
public:
  CylinderDomain(const Vec3& center, const Vec3& axis, double radius, double height, int materialId,
    const std::string& name = "Cylinder");
  const char* kind() const override { return "Cylinder"; }
  bool bounded() const override { return halfHeight_ < std::numeric_limits<double>::infinity(); }

protected:
  bool containsLocal(const Vec3& q) const override
  {
    const Vec3 w = q - center_;
    const double s = dot(w, axis_);
    return std::abs(s) <= halfHeight_ && dot(w, w) - s * s <= radius2_;
  }
  void crossingsLocal(const Vec3& qa, const Vec3& qb, std::vector<double>& ts) const override;
  BoundingBox localBounds() const override;
  /// A finite cylinder's two rims, circles sampled with chords within `sagitta` of them.
  std::vector<Crease> localCreases(double sagitta) const override;

private:
  Vec3 center_, axis_;
  double radius_, radius2_, halfHeight_;
};
}
