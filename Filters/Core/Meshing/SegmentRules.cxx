// SPDX-License-Identifier: GPL-3.0-or-later
#include "SegmentRules.h"

#include <cmath>

namespace omesh
{
namespace rules
{
bool encroaches(const Vec3& a, const Vec3& b, const Vec3& p)
{
  const Vec3 d = p - 0.5 * (a + b);
  return dot(d, d) < 0.25 * dot(b - a, b - a) * (1.0 - 1e-12);
}

std::optional<double> trimAtStarVertexT11(double length, double cut)
{
  if (length <= cut * (1.0 + 1e-9))
    return std::nullopt;
  return cut / length;
}

std::optional<double> splitEncroachedT12(const Vec3& a, const Vec3& b, bool encroached, double maxLength, double floor)
{
  const double r2 = 0.25 * dot(b - a, b - a);
  const bool tooLong = maxLength > 0 && 4.0 * r2 > maxLength * maxLength;
  if (tooLong || (encroached && std::sqrt(r2) >= floor))
    return 0.5;
  return std::nullopt;
}

RefinementPointFate refinementPointT21T31(const Vec3& p, const std::vector<NearSegment>& near, size_t* which)
{
  for (size_t k = 0; k < near.size(); ++k)
    if (encroaches(near[k].a, near[k].b, p))
    {
      if (which)
        *which = k;
      return near[k].splittable ? RefinementPointFate::SplitSegment : RefinementPointFate::Drop;
    }
  return RefinementPointFate::Insert;
}
}
}
