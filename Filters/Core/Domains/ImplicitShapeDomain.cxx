// SPDX-License-Identifier: GPL-3.0-or-later
#include "ImplicitShapeDomain.h"

#include <cmath>

namespace omesh
{
ImplicitShapeDomain::ImplicitShapeDomain(int materialId, const std::string& who)
  : materialId_(materialId)
{
  checkMaterialId(materialId, who);
  setName(who);
}

void ImplicitShapeDomain::setWorldToLocal(const AffineMap& m)
{
  (void)m.inverse(); // throws on a singular transform: such a shape has no interior
  worldToLocal_ = m;
}

void ImplicitShapeDomain::crossings(const Vec3& a, const Vec3& b, std::vector<double>& ts) const
{
  const size_t first = ts.size();
  crossingsLocal(worldToLocal_.apply(a), worldToLocal_.apply(b), ts);
  size_t kept = first;
  for (size_t i = first; i < ts.size(); ++i)
  {
    if (ts[i] >= 0.0 && ts[i] <= 1.0)
      ts[kept++] = ts[i];
  }
  ts.resize(kept);
}

BoundingBox ImplicitShapeDomain::bounds() const
{
  if (!bounded())
    return {};
  return worldToLocal_.inverseImageOf(localBounds());
}

void ImplicitShapeDomain::appendQuadraticRoots(double a, double b, double c, std::vector<double>& ts)
{
  if (a == 0.0)
  {
    if (b != 0.0)
      ts.push_back(-c / b);
    return;
  }
  const double disc = b * b - 4.0 * a * c;
  if (disc < 0.0)
    return;
  const double q = -0.5 * (b + std::copysign(std::sqrt(disc), b));
  ts.push_back(q / a);
  if (q != 0.0)
    ts.push_back(c / q);
}
}
