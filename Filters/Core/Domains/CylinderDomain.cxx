// SPDX-License-Identifier: GPL-3.0-or-later
#include "CylinderDomain.h"

#include "InputError.h"

#include <cmath>

namespace omesh
{
CylinderDomain::CylinderDomain(const Vec3& center, const Vec3& axis, double radius, double height,
  int materialId, const std::string& name)
  : ImplicitShapeDomain(materialId, name)
  , center_(center)
  , radius_(radius)
  , radius2_(radius * radius)
  , halfHeight_(0.5 * height)
{
  if (!isFinite(center) || !isFinite(axis))
    throw InputError(name + ": cylinder centre or axis has a NaN or infinite coordinate");
  const double n = norm(axis);
  if (!(n > 0.0))
    throw InputError(name + ": cylinder axis has zero length");
  axis_ = (1.0 / n) * axis;
  if (!(std::isfinite(radius) && radius > 0.0))
    throw InputError(name + ": cylinder radius must be positive and finite, got " + std::to_string(radius));
  if (!(height > 0.0)) // NaN fails too; +inf is allowed (unbounded)
    throw InputError(name + ": cylinder height must be positive (or infinite), got " + std::to_string(height));
}

void CylinderDomain::crossingsLocal(const Vec3& qa, const Vec3& qb, std::vector<double>& ts) const
{
  const Vec3 d = qb - qa;
  const Vec3 f = qa - center_;
  const double fs = dot(f, axis_), ds = dot(d, axis_);
  const Vec3 fp = f - fs * axis_, dp = d - ds * axis_;
  appendQuadraticRoots(dot(dp, dp), 2.0 * dot(fp, dp), dot(fp, fp) - radius2_, ts);
  if (bounded() && ds != 0.0)
  {
    ts.push_back((halfHeight_ - fs) / ds);
    ts.push_back((-halfHeight_ - fs) / ds);
  }
}

BoundingBox CylinderDomain::localBounds() const
{
  BoundingBox b;
  Vec3 ext;
  for (int i = 0; i < 3; ++i)
    ext[i] = std::abs(axis_[i]) * halfHeight_ + radius_ * std::sqrt(std::max(0.0, 1.0 - axis_[i] * axis_[i]));
  b.add(center_ - ext);
  b.add(center_ + ext);
  return b;
}
}
