// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include "Vec3.h"

#include <algorithm>
#include <limits>

namespace omesh
{
/// Axis-aligned box; starts empty (min > max) and grows with add().
struct BoundingBox
{
  Vec3 min{ std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
    std::numeric_limits<double>::infinity() };
  Vec3 max{ -std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(),
    -std::numeric_limits<double>::infinity() };

  bool empty() const { return min.x > max.x || min.y > max.y || min.z > max.z; }
  void add(const Vec3& p)
  {
    for (int i = 0; i < 3; ++i)
    {
      min[i] = std::min(min[i], p[i]);
      max[i] = std::max(max[i], p[i]);
    }
  }
  void add(const BoundingBox& b)
  {
    if (!b.empty())
    {
      add(b.min);
      add(b.max);
    }
  }
  bool contains(const Vec3& p) const
  {
    return p.x >= min.x && p.x <= max.x && p.y >= min.y && p.y <= max.y && p.z >= min.z &&
      p.z <= max.z;
  }
  double volume() const
  {
    return empty() ? 0.0 : (max.x - min.x) * (max.y - min.y) * (max.z - min.z);
  }
  Vec3 size() const { return max - min; }
  /// Narrows [t0, t1] to the parameters t at which a + t d lies in the box (slab method); false
  /// when none does.
  bool clip(const Vec3& a, const Vec3& d, double& t0, double& t1) const
  {
    for (int i = 0; i < 3; ++i)
    {
      if (d[i] == 0.0)
      {
        if (!(a[i] >= min[i] && a[i] <= max[i]))
          return false;
        continue;
      }
      double ta = (min[i] - a[i]) / d[i], tb = (max[i] - a[i]) / d[i];
      if (ta > tb)
        std::swap(ta, tb);
      t0 = std::max(t0, ta);
      t1 = std::min(t1, tb);
    }
    return t0 <= t1;
  }
};
}
