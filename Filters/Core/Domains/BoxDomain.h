// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include "ImplicitShapeDomain.h"

namespace omesh
{
/// Closed axis-aligned box in the local frame (oriented in the world by the affine map, as
/// vtkBox with a transform).
class BoxDomain : public ImplicitShapeDomain
{
public:
  BoxDomain(const Vec3& min, const Vec3& max, int materialId, const std::string& name = "Box");
  const char* kind() const override { return "Box"; }

protected:
  bool containsLocal(const Vec3& q) const override { return box_.contains(q); }
  void crossingsLocal(const Vec3& qa, const Vec3& qb, std::vector<double>& ts) const override;
  BoundingBox localBounds() const override { return box_; }
  /// The 12 edges, each from corner to corner (a corner is the same point in its three edges).
  std::vector<Crease> localCreases(double sagitta) const override;

private:
  BoundingBox box_;
};
}
