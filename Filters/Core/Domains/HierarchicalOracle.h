// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include "Domain.h"

#include <memory>

namespace omesh
{
/// Result of HierarchicalOracle::intersect: where, along segment ab, the material first changes.
struct Intersection
{
  bool found = false;
  double t = 0.0;          ///< parameter on ab of the change
  Vec3 point;              ///< a + t (b - a)
  int materialBefore = kOutside; ///< material on the a side
  int materialAfter = kOutside;  ///< material just past the change
};

/// Result of HierarchicalOracle::decide: which domain decides a point, and its material.
struct Decision
{
  int domain = -1;         ///< index in priority order; -1: no domain contains the point
  int material = kOutside;
  bool operator==(const Decision& o) const { return domain == o.domain && material == o.material; }
  bool operator!=(const Decision& o) const { return !(*this == o); }
  bool operator<(const Decision& o) const
  {
    return domain != o.domain ? domain < o.domain : material < o.material;
  }
};

/// The paper's hierarchical oracle (section 3.1): domains in priority order, the first domain that
/// contains a point decides its material; a cut domain that contains a point makes it outside.
/// All queries are const and thread-safe.
class HierarchicalOracle
{
public:
  /// Appends a domain with the next lower priority.
  void add(std::shared_ptr<const Domain> domain);
  const std::vector<std::shared_ptr<const Domain>>& domains() const { return domains_; }
  bool empty() const { return domains_.empty(); }

  int material(const Vec3& p) const
  {
    for (const auto& d : domains_)
    {
      const int m = d->material(p);
      if (m != kOutside)
        return d->isCut() ? kOutside : m;
    }
    return kOutside;
  }

  /// The domain that decides p (its index in priority order: the first that contains it, a cut
  /// included; -1 when none does) and p's material. Two points of one material can differ in the
  /// domain (a point cut away and one outside every domain are both outside): feature lines lie
  /// where three or more of these regions meet.
  Decision decide(const Vec3& p) const
  {
    for (size_t i = 0; i < domains_.size(); ++i)
    {
      const int m = domains_[i]->material(p);
      if (m != kOutside)
        return { static_cast<int>(i), domains_[i]->isCut() ? kOutside : m };
    }
    return {};
  }

  /// First material change on segment ab. Exact up to floating-point rounding: every domain lists
  /// its own crossing parameters (analytic for implicit shapes, segment/triangle intersections for
  /// surfaces, voxel faces for label maps) and the combined labelling is evaluated between them, so
  /// the returned point lies on a true boundary (relative error about 1e-15 of |ab|). A change that
  /// no domain reports (rounding disagreement between the inside test and the intersection, at most
  /// on a boundary) is located by bisection to 1e-12 |ab|.
  Intersection intersect(const Vec3& a, const Vec3& b) const;

  /// Whether some material lies on or right next to segment ab: at a point of it, across it, or
  /// within 1e-3 |ab| of its midpoint on either side along each axis. A segment on a boundary
  /// (e.g. a rim on a closed cut plane, whose own points are all cut away) touches the material
  /// beside it; a segment outside every domain does not and cannot become a mesh edge.
  bool touchesMaterial(const Vec3& a, const Vec3& b) const;

  /// Union of the bounds of the non-cut domains, i.e. where material can be. Throws InputError when
  /// there are no domains or a non-cut domain is unbounded (names it).
  BoundingBox bounds() const;

  /// Sorted material ids the non-cut domains can return.
  std::vector<int> materials() const;

private:
  std::vector<std::shared_ptr<const Domain>> domains_;
};
}
