// SPDX-License-Identifier: GPL-3.0-or-later
#include "BoxDomain.h"

#include "InputError.h"

#include <limits>

namespace omesh
{
BoxDomain::BoxDomain(const Vec3& min, const Vec3& max, int materialId, const std::string& name)
  : ImplicitShapeDomain(materialId, name)
{
  if (!isFinite(min) || !isFinite(max))
    throw InputError(name + ": box bounds have a NaN or infinite value");
  if (!(min.x < max.x && min.y < max.y && min.z < max.z))
    throw InputError(name + ": box bounds are empty (need min < max on every axis)");
  box_.add(min);
  box_.add(max);
}

void BoxDomain::crossingsLocal(const Vec3& qa, const Vec3& qb, std::vector<double>& ts) const
{
  // Slab method: the entry and exit parameters are the only places the box indicator changes.
  const Vec3 d = qb - qa;
  double t0 = -std::numeric_limits<double>::infinity();
  double t1 = std::numeric_limits<double>::infinity();
  for (int i = 0; i < 3; ++i)
  {
    if (d[i] == 0.0)
    {
      if (qa[i] < box_.min[i] || qa[i] > box_.max[i])
        return;
      continue;
    }
    double ta = (box_.min[i] - qa[i]) / d[i];
    double tb = (box_.max[i] - qa[i]) / d[i];
    if (ta > tb)
      std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
  if (t0 <= t1)
  {
    ts.push_back(t0);
    ts.push_back(t1);
  }
}

std::vector<Crease> BoxDomain::localCreases(double) const
{
  std::vector<Crease> edges;
  for (int axis = 0; axis < 3; ++axis)
  {
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    for (int su = 0; su < 2; ++su)
      for (int sv = 0; sv < 2; ++sv)
      {
        Vec3 a, nu, nv;
        a[u] = su ? box_.max[u] : box_.min[u];
        a[v] = sv ? box_.max[v] : box_.min[v];
        a[axis] = box_.min[axis];
        Vec3 b = a;
        b[axis] = box_.max[axis];
        nu[u] = su ? 1.0 : -1.0;
        nv[v] = sv ? 1.0 : -1.0;
        edges.push_back({ { a, b }, { { nu, nv } }, 90.0 });
      }
  }
  return edges;
}
}
