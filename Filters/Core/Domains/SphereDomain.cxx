// SPDX-License-Identifier: GPL-3.0-or-later
#include "SphereDomain.h"

#include "InputError.h"

#include <cmath>

namespace omesh
{
SphereDomain::SphereDomain(const Vec3& center, double radius, int materialId, const std::string& name)
  : ImplicitShapeDomain(materialId, name)
  , center_(center)
  , radius_(radius)
  , radius2_(radius * radius)
{
  if (!(std::isfinite(radius) && radius > 0.0))
    throw InputError(name + ": sphere radius must be positive and finite, got " + std::to_string(radius));
  if (!isFinite(center))
    throw InputError(name + ": sphere centre has a NaN or infinite coordinate");
}

void SphereDomain::crossingsLocal(const Vec3& qa, const Vec3& qb, std::vector<double>& ts) const
{
  const Vec3 d = qb - qa;
  const Vec3 f = qa - center_;
  appendQuadraticRoots(dot(d, d), 2.0 * dot(f, d), dot(f, f) - radius2_, ts);
}

BoundingBox SphereDomain::localBounds() const
{
  BoundingBox b;
  b.add(center_ - Vec3{ radius_, radius_, radius_ });
  b.add(center_ + Vec3{ radius_, radius_, radius_ });
  return b;
}
}
