// SPDX-License-Identifier: GPL-3.0-or-later
// PRIVATE (includes CGAL): the hierarchical oracle as a CGAL Mesh_3 domain. Include it only from
// the mesher's translation unit.
#pragma once

#include "HierarchicalOracle.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Labeled_mesh_domain_3.h>
#include <CGAL/Random.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <tuple>
#include <vector>

namespace omesh::cgal
{
using K = CGAL::Exact_predicates_inexact_constructions_kernel;

inline Vec3 toVec(const K::Point_3& p) { return { p.x(), p.y(), p.z() }; }
inline K::Point_3 toPoint(const Vec3& p) { return { p.x, p.y, p.z }; }

/// Subdomain index of a material: 0 is outside (Mesh_3's null subdomain), material m is m + 1.
inline int subdomainOf(int material) { return material + 1; }
inline int materialOf(int subdomain) { return subdomain - 1; }

/// CGAL's labelled domain with the oracle as labelling function, whose intersection queries are
/// replaced by the oracle's exact ones (the base class bisects) and whose initial points sample the
/// boundary of every domain (so small materials, a screw, are never missed).
class OracleMeshDomain : public CGAL::Labeled_mesh_domain_3<K>
{
public:
  using Base = CGAL::Labeled_mesh_domain_3<K>;

  OracleMeshDomain(const HierarchicalOracle& oracle, const BoundingBox& box, unsigned seed)
    : Base(std::function<int(const K::Point_3&)>(
             [&oracle](const K::Point_3& p) { return subdomainOf(oracle.material(toVec(p))); }),
        K::Iso_cuboid_3(box.min.x, box.min.y, box.min.z, box.max.x, box.max.y, box.max.z))
    , oracle_(oracle)
    , box_(box)
    , seed_(seed)
    , coordinateNoise_(1e-30 *
        std::max({ std::abs(box.min.x), std::abs(box.min.y), std::abs(box.min.z), std::abs(box.max.x),
          std::abs(box.max.y), std::abs(box.max.z) }))
  {
  }

  const HierarchicalOracle& oracle() const { return oracle_; }

  /// The first material change along a segment, as Mesh_3 wants it. The segment is clipped to the
  /// domain's box first: dual edges of flat cells reach 1e14 away, where a + t (b - a) has lost
  /// every digit of the part near the surface.
  Intersection intersectSegment(const K::Point_3& pa, const K::Point_3& pb) const
  {
    Vec3 a = toVec(pa), b = toVec(pb);
    if (!clip(a, b))
      return Intersection();
    const omesh::Intersection x = oracle_.intersect(a, b);
    if (!x.found)
      return Intersection();
    const Surface_patch_index patch = make_surface_index(subdomainOf(x.materialBefore), subdomainOf(x.materialAfter));
    return Intersection(toPoint(onCoordinatePlanes(x.point)), index_from_surface_patch_index(patch), 2);
  }

  /// p with each coordinate below 1e-30 of the domain's scale set to 0. Near 0 floating point
  /// resolves far below any other place: a dual segment that starts on a face on x = 0 up to
  /// rounding (x = -2.8e-17) crosses it at t = 1e-16, and a + t (b - a) cancels to x = -3e-33 (or
  /// -1.7e-49), where on x = 1.5 it would be 1.5 or an ulp off it. Such a surface vertex lies in the
  /// material on the other side of the face, and refinement around it runs away (on generated CAD
  /// parts: a facet's point repeating a vertex, or thousands of vertices in one cluster). Not a few
  /// ulps of the scale: points that rounding put 1e-15 off x = 0 elsewhere (feature points) would
  /// then lie 4e-15 from snapped ones, as duplicate vertices.
  Vec3 onCoordinatePlanes(Vec3 p) const
  {
    for (int i = 0; i < 3; ++i)
      if (std::abs(p[i]) < coordinateNoise_)
        p[i] = 0.0;
    return p;
  }

  /// Rays and lines become segments through the box (then clipped exactly by intersectSegment).
  Intersection intersectClipped(const K::Ray_3& r) const
  {
    const Vec3 s = toVec(r.source()), d = toVec(r.point(1)) - s;
    if (!(norm(d) > 0))
      return Intersection();
    return intersectSegment(r.source(), toPoint(s + (farReach() / norm(d)) * d));
  }
  Intersection intersectClipped(const K::Line_3& l) const
  {
    const Vec3 s = toVec(l.point(0)), d = toVec(l.point(1)) - s;
    if (!(norm(d) > 0))
      return Intersection();
    const Vec3 far = (farReach() / norm(d)) * d;
    return intersectSegment(toPoint(s - far), toPoint(s + far));
  }

  /// Clips ab to the box (slab method); the end moved onto a face gets that face's coordinate
  /// exactly. False when the segment misses the box.
  bool clip(Vec3& a, Vec3& b) const
  {
    auto inBox = [&](const Vec3& p) {
      return p.x >= box_.min.x && p.y >= box_.min.y && p.z >= box_.min.z && p.x <= box_.max.x &&
        p.y <= box_.max.y && p.z <= box_.max.z;
    };
    if (inBox(a) && inBox(b)) // (the slab method keeps both ends: the common case, done at once)
      return true;
    if (!isFinite(a) || !isFinite(b)) // the dual of a flat cell
      return false;
    const Vec3 d = b - a;
    double t0 = 0.0, t1 = 1.0;
    int axis0 = -1, axis1 = -1;
    double face0 = 0, face1 = 0;
    for (int i = 0; i < 3; ++i)
    {
      if (d[i] == 0.0)
      {
        if (a[i] < box_.min[i] || a[i] > box_.max[i])
          return false;
        continue;
      }
      double ta = (box_.min[i] - a[i]) / d[i], tb = (box_.max[i] - a[i]) / d[i];
      double fa = box_.min[i], fb = box_.max[i];
      if (ta > tb)
      {
        std::swap(ta, tb);
        std::swap(fa, fb);
      }
      if (ta > t0)
      {
        t0 = ta;
        axis0 = i;
        face0 = fa;
      }
      if (tb < t1)
      {
        t1 = tb;
        axis1 = i;
        face1 = fb;
      }
    }
    if (!(t0 < t1))
      return false;
    const Vec3 a0 = a, b0 = b;
    if (axis0 >= 0)
    {
      a = lerp(a0, b0, t0);
      a[axis0] = face0;
    }
    if (axis1 >= 0)
    {
      b = lerp(a0, b0, t1);
      b[axis1] = face1;
    }
    return true;
  }

  struct Do_intersect_surface
  {
    const OracleMeshDomain& d;
    Surface_patch operator()(const K::Segment_3& s) const { return patch(d.intersectSegment(s.source(), s.target())); }
    Surface_patch operator()(const K::Ray_3& r) const { return patch(d.intersectClipped(r)); }
    Surface_patch operator()(const K::Line_3& l) const { return patch(d.intersectClipped(l)); }

  private:
    Surface_patch patch(const Intersection& x) const
    {
      if (std::get<2>(x) == 0)
        return Surface_patch();
      return Surface_patch(d.surface_patch_index(std::get<1>(x)));
    }
  };
  Do_intersect_surface do_intersect_surface_object() const { return { *this }; }

  struct Construct_intersection
  {
    const OracleMeshDomain& d;
    Intersection operator()(const K::Segment_3& s) const { return d.intersectSegment(s.source(), s.target()); }
    Intersection operator()(const K::Ray_3& r) const { return d.intersectClipped(r); }
    Intersection operator()(const K::Line_3& l) const { return d.intersectClipped(l); }
  };
  Construct_intersection construct_intersection_object() const { return { *this }; }

  /// Boundary points of every non-cut domain, as seen through the hierarchy: rays from the
  /// domain's centre, each change of material along them. Points closer than 1/50 of their
  /// domain's diagonal to an accepted point or to a point of avoidInitialPointsNear() are
  /// skipped: when the centre lies on a flat face (CAD parts, axis-aligned), half of the rays cross
  /// that face within rounding of the centre, and such near-coincident points seed clusters of
  /// micro tetrahedra that no refinement removes (half the rays of an L-shaped part gave 10 points
  /// within 1e-5 mm of each other).
  struct Construct_initial_points
  {
    const OracleMeshDomain& d;
    template <class OutputIterator>
    OutputIterator operator()(OutputIterator pts, const int n = 20) const
    {
      CGAL::Random rng(d.seed_);
      std::vector<Vec3> taken;
      auto farFromAll = [&](const Vec3& p, double sep) {
        const std::vector<Vec3>* lists[] = { &taken, &d.avoid_ };
        for (const std::vector<Vec3>* list : lists)
          for (const Vec3& q : *list)
            if (dot(p - q, p - q) < sep * sep)
              return false;
        return true;
      };
      for (const auto& domain : d.oracle_.domains())
      {
        if (domain->isCut() || !domain->bounded())
          continue;
        const BoundingBox b = domain->bounds();
        const Vec3 c = 0.5 * (b.min + b.max);
        const double reach = norm(b.size()) + 1e-9;
        const double sep = 0.02 * norm(b.size());
        int found = 0;
        for (int k = 0; k < 20 * n && found < n; ++k)
        {
          Vec3 dir{ rng.get_double(-1, 1), rng.get_double(-1, 1), rng.get_double(-1, 1) };
          const double l = norm(dir);
          if (!(l > 1e-3 && l <= 1.0))
            continue;
          Vec3 a = c;
          const Vec3 end = c + (reach / l) * dir;
          for (int hit = 0; hit < 4; ++hit)
          {
            const omesh::Intersection x = d.oracle_.intersect(a, end);
            if (!x.found)
              break;
            if (farFromAll(x.point, sep))
            {
              const Surface_patch_index patch =
                d.make_surface_index(subdomainOf(x.materialBefore), subdomainOf(x.materialAfter));
              *pts++ = std::make_pair(toPoint(x.point), d.index_from_surface_patch_index(patch));
              taken.push_back(x.point);
              ++found;
            }
            a = lerp(x.point, end, 1e-9); // step past this change
          }
        }
      }
      return pts;
    }
  };
  /// Initial points keep away from these (the constrained segments' points, inserted first).
  void avoidInitialPointsNear(std::vector<Vec3> points) { avoid_ = std::move(points); }
  Construct_initial_points construct_initial_points_object() const { return { *this }; }

private:
  double farReach() const { return 4.0 * norm(box_.size()) + norm(box_.max) + norm(box_.min); }

  const HierarchicalOracle& oracle_;
  BoundingBox box_;
  unsigned seed_;
  double coordinateNoise_; ///< onCoordinatePlanes: 1e-30 of the box's largest coordinate
  std::vector<Vec3> avoid_;
};
}
