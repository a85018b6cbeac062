// SPDX-License-Identifier: GPL-3.0-or-later
#include "CylinderDomain.h"

#include "InputError.h"

#include <algorithm>
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

std::vector<Crease> CylinderDomain::localCreases(double sagitta) const
{
  if (!bounded())
    return {};
  // Chords of angle theta stay within r (1 - cos(theta / 2)) of the circle.
  const double theta = 2.0 * std::acos(std::clamp(1.0 - sagitta / radius_, -1.0, 1.0));
  const int n = std::clamp(static_cast<int>(std::ceil(2.0 * M_PI / std::max(theta, 1e-12))), 16, 100000);
  Vec3 e1 = cross(axis_, std::abs(axis_.x) < 0.9 ? Vec3{ 1, 0, 0 } : Vec3{ 0, 1, 0 });
  e1 = (1.0 / norm(e1)) * e1;
  const Vec3 e2 = cross(axis_, e1);
  std::vector<Crease> rims;
  for (double side : { -1.0, 1.0 })
  {
    Crease rim;
    const Vec3 centre = center_ + (side * halfHeight_) * axis_;
    for (int k = 0; k <= n; ++k)
    {
      const double phi = 2.0 * M_PI * (k % n) / n;
      rim.points.push_back(centre + radius_ * (std::cos(phi) * e1 + std::sin(phi) * e2));
      if (k < n)
      {
        const double mid = 2.0 * M_PI * (k + 0.5) / n;
        rim.normals.push_back({ side * axis_, std::cos(mid) * e1 + std::sin(mid) * e2 });
      }
    }
    rims.push_back(std::move(rim));
  }
  return rims;
}
}
