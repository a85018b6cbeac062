// SPDX-License-Identifier: GPL-3.0-or-later
#include "TriangleDistance.h"

#include "InputError.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <algorithm>
#include <cmath>

namespace omesh
{
namespace
{
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Triangles = std::vector<K::Triangle_3>;
using Primitive = CGAL::AABB_triangle_primitive<K, Triangles::const_iterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, Primitive>>;

/// One-sided: the farthest sample of `from` from the triangles of `to`.
double oneSided(const TriangleSurface& from, const TriangleDistance& to)
{
  double worst = 0.0;
  for (const auto& t : from.triangles)
  {
    const Vec3& a = from.points[t[0]];
    const Vec3& b = from.points[t[1]];
    const Vec3& c = from.points[t[2]];
    for (const Vec3& p : { a, b, c, 0.5 * (a + b), 0.5 * (b + c), 0.5 * (a + c), (1.0 / 3.0) * (a + b + c) })
      worst = std::max(worst, to.distance(p));
  }
  return worst;
}
}

struct TriangleDistance::Impl
{
  Triangles triangles;
  Tree tree;
};

TriangleDistance::TriangleDistance(const TriangleSurface& surface)
  : impl_(std::make_unique<Impl>())
{
  if (surface.triangles.empty())
    throw InputError("distance to an empty surface");
  for (const auto& t : surface.triangles)
  {
    const auto P = [&](int i) { return K::Point_3(surface.points[i].x, surface.points[i].y, surface.points[i].z); };
    impl_->triangles.emplace_back(P(t[0]), P(t[1]), P(t[2]));
  }
  impl_->tree.insert(impl_->triangles.begin(), impl_->triangles.end());
  impl_->tree.accelerate_distance_queries();
}

TriangleDistance::~TriangleDistance() = default;

double TriangleDistance::distance(const Vec3& p) const
{
  return std::sqrt(impl_->tree.squared_distance(K::Point_3(p.x, p.y, p.z)));
}

double TriangleDistance::hausdorff(const TriangleSurface& a, const TriangleSurface& b)
{
  const TriangleDistance toA(a), toB(b);
  return std::max(oneSided(a, toB), oneSided(b, toA));
}
}
