// SPDX-License-Identifier: GPL-3.0-or-later
#include "HalfSpaceDomain.h"

#include "InputError.h"

namespace omesh
{
HalfSpaceDomain::HalfSpaceDomain(
  const Vec3& origin, const Vec3& normal, int materialId, const std::string& name)
  : ImplicitShapeDomain(materialId, name)
  , origin_(origin)
  , normal_(normal)
{
  if (!isFinite(origin) || !isFinite(normal))
    throw InputError(name + ": plane origin or normal has a NaN or infinite coordinate");
  const double n = norm(normal);
  if (!(n > 0.0))
    throw InputError(name + ": plane normal has zero length");
  normal_ = (1.0 / n) * normal;
}

void HalfSpaceDomain::crossingsLocal(const Vec3& qa, const Vec3& qb, std::vector<double>& ts) const
{
  const double sa = dot(qa - origin_, normal_);
  const double sb = dot(qb - origin_, normal_);
  if (sa != sb)
    ts.push_back(sa / (sa - sb));
}
}
