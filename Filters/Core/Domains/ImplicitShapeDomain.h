// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include "AffineMap.h"
#include "Domain.h"

namespace omesh
{
/// A single-material domain given by an analytic shape in its own frame. The optional world-to-local
/// affine map carries VTK implicit-function transforms (a sphere under a scaling is an ellipsoid).
class ImplicitShapeDomain : public Domain
{
public:
  int material(const Vec3& p) const final
  {
    return containsLocal(worldToLocal_.apply(p)) ? materialId_ : kOutside;
  }
  void crossings(const Vec3& a, const Vec3& b, std::vector<double>& ts) const final;
  BoundingBox bounds() const final;
  std::vector<int> materials() const final { return { materialId_ }; }
  /// The shape's local creases (localCreases) carried into the world by the affine map.
  std::vector<Crease> creases(double featureAngle, double sagitta) const final;

  int materialId() const { return materialId_; }
  const AffineMap& worldToLocal() const { return worldToLocal_; }
  void setWorldToLocal(const AffineMap& m);

protected:
  ImplicitShapeDomain(int materialId, const std::string& who);

  virtual bool containsLocal(const Vec3& q) const = 0;
  /// Candidate parameters in local coordinates; the base class keeps those in [0, 1].
  virtual void crossingsLocal(const Vec3& qa, const Vec3& qb, std::vector<double>& ts) const = 0;
  virtual BoundingBox localBounds() const = 0;
  /// Creases in the local frame, curved ones within `sagitta`; none by default (smooth shapes).
  virtual std::vector<Crease> localCreases(double sagitta) const
  {
    (void)sagitta;
    return {};
  }

  /// Real roots of a t^2 + b t + c = 0 appended to ts (numerically stable form).
  static void appendQuadraticRoots(double a, double b, double c, std::vector<double>& ts);

private:
  int materialId_;
  AffineMap worldToLocal_;
};
}
