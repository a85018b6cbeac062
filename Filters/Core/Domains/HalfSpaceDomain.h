// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include "ImplicitShapeDomain.h"

namespace omesh
{
/// Closed half-space (p - origin) . normal <= 0: like vtkPlane, it contains the side its normal
/// points away from. Unbounded, so mostly useful as a cut.
class HalfSpaceDomain : public ImplicitShapeDomain
{
public:
  HalfSpaceDomain(const Vec3& origin, const Vec3& normal, int materialId, const std::string& name = "Plane");
  const char* kind() const override { return "Plane"; }
  bool bounded() const override { return false; }

protected:
  bool containsLocal(const Vec3& q) const override { return dot(q - origin_, normal_) <= 0.0; }
  void crossingsLocal(const Vec3& qa, const Vec3& qb, std::vector<double>& ts) const override;
  BoundingBox localBounds() const override { return {}; }

private:
  Vec3 origin_, normal_;
};
}
