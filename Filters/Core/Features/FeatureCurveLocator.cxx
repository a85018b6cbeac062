// SPDX-License-Identifier: GPL-3.0-or-later
#include "FeatureCurveLocator.h"

#include <cmath>
#include <utility>

namespace omesh::featurelines
{
bool FeatureCurveLocator::curveBetween(const Vec3& pa, const Vec3& pb, const Signature& regions, Crossing& m) const
{
  const double L = norm(pb - pa);
  if (!(L > 4 * precision_))
    return false;
  return curveInSquare(0.5 * (pa + pb), pb - pa, L, regions, m);
}

bool FeatureCurveLocator::curveInSquare(
  const Vec3& centre, const Vec3& normal, double L, const Signature& regions, Crossing& m) const
{
  if (!(norm(normal) > 0))
    return false;
  const Vec3 n = (1.0 / norm(normal)) * normal;
  const int axis = std::abs(n.x) <= std::abs(n.y) && std::abs(n.x) <= std::abs(n.z) ? 0 : std::abs(n.y) <= std::abs(n.z) ? 1 : 2;
  Vec3 e;
  e[axis] = 1.0;
  Vec3 e1 = cross(n, e);
  e1 = (1.0 / norm(e1)) * e1;
  const Vec3 e2 = cross(n, e1);
  const Vec3 o = centre - (0.5 * L) * (e1 + e2);
  Rect q{ o, L * e1, L * e2, regionsAlong(oracle_, o, o + L * e1), regionsAlong(oracle_, o + L * e2, o + L * (e1 + e2)),
    regionsAlong(oracle_, o, o + L * e2), regionsAlong(oracle_, o + L * e1, o + L * (e1 + e2)) };
  if (!holdsCurve(loopOf(q)))
    return false;
  m = locate(oracle_, std::move(q), precision_);
  return m.regions == regions;
}
}
