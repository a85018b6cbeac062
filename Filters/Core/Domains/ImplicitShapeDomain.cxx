// SPDX-License-Identifier: GPL-3.0-or-later
#include "ImplicitShapeDomain.h"

#include <algorithm>
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

std::vector<Crease> ImplicitShapeDomain::creases(double featureAngle, double sagitta) const
{
  // World x = inverse(local); a local plane n.q = c is (A^T n).x = c' in the world (A: the linear
  // part of worldToLocal). The inverse's size bounds how far a local sagitta stretches.
  const AffineMap toWorld = worldToLocal_.inverse();
  const auto& a = worldToLocal_.rows();
  const auto& w = toWorld.rows();
  double stretch = 0.0;
  for (int i : { 0, 1, 2, 4, 5, 6, 8, 9, 10 })
    stretch += w[i] * w[i];
  std::vector<Crease> world = localCreases(sagitta / std::sqrt(stretch));
  const double cosLimit = std::cos(featureAngle * M_PI / 180.0);
  std::vector<Crease> kept;
  for (Crease& c : world)
  {
    for (Vec3& p : c.points)
      p = toWorld.apply(p);
    double smallest = 180.0;
    for (auto& pair : c.normals)
      for (Vec3& n : pair)
      {
        const Vec3 m{ a[0] * n.x + a[4] * n.y + a[8] * n.z, a[1] * n.x + a[5] * n.y + a[9] * n.z,
          a[2] * n.x + a[6] * n.y + a[10] * n.z };
        n = (1.0 / norm(m)) * m;
      }
    bool sharp = false;
    for (const auto& pair : c.normals)
    {
      const double cosine = std::clamp(dot(pair[0], pair[1]), -1.0, 1.0);
      sharp = sharp || cosine < cosLimit;
      smallest = std::min(smallest, 180.0 - std::acos(cosine) * 180.0 / M_PI);
    }
    c.dihedral = smallest;
    if (sharp)
      kept.push_back(std::move(c));
  }
  return kept;
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
