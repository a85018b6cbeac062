// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include "ImplicitShapeDomain.h"

namespace omesh
{
/// Closed ball |p - center| <= radius (in the local frame).
class SphereDomain : public ImplicitShapeDomain
{
public:
  /// Throws InputError for a radius that is not finite and positive, or a non-finite centre.
  SphereDomain(const Vec3& center, double radius, int materialId, const std::string& name = "Sphere");
  const char* kind() const override { return "Sphere"; }
  const Vec3& center() const { return center_; }
  double radius() const { return radius_; }

protected:
  bool containsLocal(const Vec3& q) const override
  {
    const Vec3 d = q - center_;
    return dot(d, d) <= radius2_;
  }
  void crossingsLocal(const Vec3& qa, const Vec3& qb, std::vector<double>& ts) const override;
  BoundingBox localBounds() const override;

private:
  Vec3 center_;
  double radius_, radius2_;
};
}
