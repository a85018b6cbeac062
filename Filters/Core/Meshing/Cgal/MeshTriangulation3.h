// SPDX-License-Identifier: GPL-3.0-or-later
// Private to the mesher's translation units (includes CGAL): the triangulation and complex types of
// the mesher, sequential (OracleMesher.cxx) or parallel (ParallelRefinement.cxx, CGAL's
// Parallel_tag: concurrent containers and a lock grid). Both share the geometric traits, the vertex
// and cell bases, so a complex can be copied from one to the other (ParallelRefinement.cxx, PackedComplex.h).
#pragma once

#include "CellRefinementQueue.h"
#include "MesherCriteria3.h"
#include "OracleMeshDomain.h"
#include "SurfaceCentreCell3.h"

#include <CGAL/Mesh_complex_3_in_triangulation_3.h>
#include <CGAL/Mesh_criteria_3.h>
#include <CGAL/Mesh_domain_with_polyline_features_3.h>
#include <CGAL/Mesh_triangulation_3.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace omesh::cgal
{
using MeshDomain = CGAL::Mesh_domain_with_polyline_features_3<OracleMeshDomain>;
using RobustTraits = CGAL::Robust_weighted_circumcenter_filtered_traits_3<K>;

/// CGAL's robust weighted circumcentre keeps its floating-point value as soon as that lies inside
/// the cell's power sphere. A nearly flat cell (four ball centres on the edges of one flat face) has
/// a huge sphere, and the value can be off by its radius (seen: 27 mm, ball centres 3.5 mm apart):
/// the facet duals built from it are wrong, a surface centre on such a dual can fall inside
/// protecting balls, and CGAL fails ("A facet is not in conflict with its refinement point"). For a
/// cell with weights this one also asks for equal power to the four points, else takes CGAL's exact
/// construction. Unweighted cells keep CGAL's value (no point is hidden there: CGAL's own exact
/// fallback catches a facet outside its refinement point's conflict zone).
struct AccurateWeightedCircumcenter : RobustTraits::Construct_weighted_circumcenter_3
{
  using Base = RobustTraits::Construct_weighted_circumcenter_3;
  using Base::Base;
  using Base::operator();
  K::Point_3 operator()(const K::Weighted_point_3& p, const K::Weighted_point_3& q, const K::Weighted_point_3& r,
    const K::Weighted_point_3& s, bool forceExact = false) const
  {
    const bool unweighted = p.weight() == 0 && q.weight() == 0 && r.weight() == 0 && s.weight() == 0;
    if (unweighted && !forceExact)
    {
      // CGAL computes this t and keeps it where its predicate (Side_of_oriented_sphere_3, ~200
      // instructions a cell) shows t inside the cell's circumsphere; doubles show that for all
      // but nearly flat cells (certainlyInsideCircumsphere): the same point, else CGAL decides
      double nx, ny, nz, den;
      CGAL::determinants_for_circumcenterC3(p.x(), p.y(), p.z(), q.x(), q.y(), q.z(), r.x(), r.y(), r.z(), s.x(),
        s.y(), s.z(), nx, ny, nz, den);
      if (den != 0.0)
      {
        const double inv = 1.0 / (2.0 * den);
        const K::Point_3 t(p.x() + nx * inv, p.y() - ny * inv, p.z() + nz * inv);
        if (certainlyInsideCircumsphere(p.point(), q.point(), r.point(), s.point(), den, t))
          return t;
      }
    }
    const K::Point_3 c = Base::operator()(p, q, r, s, forceExact);
    if (forceExact || unweighted)
      return c;
    double lo = std::numeric_limits<double>::infinity(), hi = -lo, scale = 0.0;
    for (const K::Weighted_point_3* w : { &p, &q, &r, &s })
    {
      const double d2 = CGAL::squared_distance(c, w->point());
      lo = std::min(lo, d2 - w->weight());
      hi = std::max(hi, d2 - w->weight());
      scale = std::max(scale, d2 + w->weight());
    }
    return hi - lo <= 1e-10 * scale ? c : Base::operator()(p, q, r, s, true);
  }

  /// Three points (the facet criterion's distance, every facet): CGAL keeps its floating-point
  /// circumcentre t where an exact predicate, in interval arithmetic, shows t inside the sphere
  /// that has the circumcircle of pqr as equator (~1,000 instructions a call, 7 % of a coarse label
  /// map's refinement); else its exact construction. Unweighted, this computes the same t, as CGAL
  /// computes it, and keeps it where doubles already show that (certainlyInsideEquatorSphere);
  /// otherwise CGAL's construction decides. The same points either way.
  K::Point_3 operator()(const K::Weighted_point_3& p, const K::Weighted_point_3& q, const K::Weighted_point_3& r) const
  {
    if (p.weight() == 0 && q.weight() == 0 && r.weight() == 0)
    {
      double nx, ny, nz, den;
      CGAL::determinants_for_weighted_circumcenterC3(p.x(), p.y(), p.z(), p.weight(), q.x(), q.y(), q.z(), q.weight(),
        r.x(), r.y(), r.z(), r.weight(), nx, ny, nz, den);
      if (den != 0.0)
      {
        const double inv = 1.0 / (2.0 * den);
        const K::Point_3 t(p.x() + nx * inv, p.y() - ny * inv, p.z() + nz * inv);
        if (certainlyInsideEquatorSphere(p.point(), q.point(), r.point(), t))
          return t;
      }
    }
    return Base::operator()(p, q, r);
  }

  /// True only where t lies strictly inside the sphere whose equator is the circumcircle of pqr
  /// (centre c, radius |c - p|), shown in doubles with rounding bounded generously: with x = t - p,
  /// a = q - p, b = r - p and e = t - c, e.a = x.a - |a|^2 / 2, e.b = x.b - |b|^2 / 2 and
  /// e.n = x.n (n = a x b) bound |e|^2 <= ((e.a)^2 + (e.b)^2)(|a|^2 + |b|^2) / |n|^2 + (x.n)^2 / |n|^2
  /// (the in-plane part through the Gram matrix's smallest eigenvalue, at least |n|^2 / (|a|^2 +
  /// |b|^2)); |e| <= |x| / 4 then gives a radius |x - e| >= 3 |e| > |e|. Every rounding error
  /// below is at most a few 1e-16 of L2 = |a|^2 + |b|^2 + |x|^2 (of L2^1.5 for x.n); 1e-14 covers
  /// them many times. Flat triangles (|n| < 1e-6 L2) are left to the exact predicate.
  static bool certainlyInsideEquatorSphere(const K::Point_3& p, const K::Point_3& q, const K::Point_3& r, const K::Point_3& t)
  {
    const double a[3] = { q.x() - p.x(), q.y() - p.y(), q.z() - p.z() };
    const double b[3] = { r.x() - p.x(), r.y() - p.y(), r.z() - p.z() };
    const double x[3] = { t.x() - p.x(), t.y() - p.y(), t.z() - p.z() };
    auto dot = [](const double* u, const double* v) { return u[0] * v[0] + u[1] * v[1] + u[2] * v[2]; };
    const double n[3] = { a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0] };
    const double aa = dot(a, a), bb = dot(b, b), xx = dot(x, x), nn = dot(n, n);
    const double l2 = aa + bb + xx;
    constexpr double tol = 1e-14;
    const double nLength = std::sqrt(nn), nError = tol * l2;
    if (!(nLength >= 1e-6 * l2) || !std::isfinite(l2))
      return false;
    const double ea = std::abs(dot(x, a) - 0.5 * aa) + tol * l2, eb = std::abs(dot(x, b) - 0.5 * bb) + tol * l2;
    const double xn = std::abs(dot(x, n)) + tol * l2 * std::sqrt(l2);
    const double nLow = nLength * (1.0 - tol) - nError;
    const double bound = ((ea * ea + eb * eb) * (aa + bb) * (1.0 + tol) + xn * xn) / (nLow * nLow);
    return bound * (1.0 + 1e-12) <= xx * (1.0 - tol) / 16.0;
  }

  /// True only where t lies strictly inside the circumsphere of pqrs (centre c) and pqrs is
  /// positively oriented, shown in doubles with rounding bounded generously; `det` is det M (rows
  /// a = q - p, b = r - p, d = s - p) as doubles compute it (CGAL's den). With x = t - p and
  /// e = t - c, M e = (x.a - |a|^2 / 2, x.b - |b|^2 / 2, x.d - |d|^2 / 2), and |e| <= |M e| /
  /// sigma_min(M) <= |M e| |M|_F^2 / (2 |det M|) (sigma_1 sigma_2 <= |M|_F^2 / 2); |e| <= |x| / 4
  /// then gives a radius |x - e| >= 3 |e| > |e|. Every rounding error below is at most a few 1e-16
  /// of L2 = |a|^2 + |b|^2 + |d|^2 + |x|^2 (of L2^1.5 for det M); 1e-14 covers them many times.
  /// Nearly flat cells (det^2 < 1e-12 L2^3, where 1e-14 L2^1.5 would exceed 1e-8 det) are left to
  /// the exact predicate, and so is a negative orientation (never a cell's). Unweighted cells only.
  static bool certainlyInsideCircumsphere(const K::Point_3& p, const K::Point_3& q, const K::Point_3& r,
    const K::Point_3& s, double det, const K::Point_3& t)
  {
    const double a[3] = { q.x() - p.x(), q.y() - p.y(), q.z() - p.z() };
    const double b[3] = { r.x() - p.x(), r.y() - p.y(), r.z() - p.z() };
    const double d[3] = { s.x() - p.x(), s.y() - p.y(), s.z() - p.z() };
    const double x[3] = { t.x() - p.x(), t.y() - p.y(), t.z() - p.z() };
    auto dot = [](const double* u, const double* v) { return u[0] * v[0] + u[1] * v[1] + u[2] * v[2]; };
    const double aa = dot(a, a), bb = dot(b, b), dd = dot(d, d), xx = dot(x, x);
    const double l2 = aa + bb + dd + xx;
    constexpr double tol = 1e-14;
    // (l2 within 1e+-50: no product below underflows or overflows, NaN and infinity excluded)
    if (!(l2 >= 1e-50 && l2 <= 1e50 && det > 0.0 && det * det >= 1e-12 * (l2 * l2 * l2)))
      return false;
    const double ea = std::abs(dot(x, a) - 0.5 * aa) + tol * l2, eb = std::abs(dot(x, b) - 0.5 * bb) + tol * l2,
                 ed = std::abs(dot(x, d) - 0.5 * dd) + tol * l2;
    const double frobenius = (aa + bb + dd) * (1.0 + tol);
    const double detLow = det * (1.0 - 1e-8);
    const double bound = (ea * ea + eb * eb + ed * ed) * (1.0 + tol) * frobenius * frobenius / (4.0 * detLow * detLow);
    return bound * (1.0 + 1e-12) <= xx * (1.0 - tol) / 16.0;
  }
};

struct GeomTraits : RobustTraits
{
  using Construct_weighted_circumcenter_3 = AccurateWeightedCircumcenter;
  GeomTraits(const K& k = K())
    : RobustTraits(k)
  {
  }
  Construct_weighted_circumcenter_3 construct_weighted_circumcenter_3_object() const
  {
    return Construct_weighted_circumcenter_3(static_cast<const K&>(*this));
  }
};

// As CGAL::Mesh_triangulation_3<MeshDomain, K, ConcurrencyTag>::type, with GeomTraits.
using VertexBase = CGAL::Mesh_vertex_generator_3<GeomTraits, CGAL::Mesh_3::internal::Indices_tuple_t<MeshDomain>, MeshDomain::Index>;
// The cell: CGAL's compact one with the facets' surface centres out of line (SurfaceCentreCell3.h).
using CellBase = SurfaceCentreCellGenerator3<GeomTraits, MeshDomain::Subdomain_index,
  MeshDomain::Surface_patch_index, MeshDomain::Index>;

/// The mesher's types for CGAL::Sequential_tag or CGAL::Parallel_tag.
template <class ConcurrencyTag>
struct MeshTriangulation3
{
  struct Tds : CGAL::Triangulation_data_structure_3<VertexBase, CellBase, ConcurrencyTag>
  {
  };
  using Tr = CGAL::Mesh_3_regular_triangulation_3_wrapper<GeomTraits, Tds>;
  using C3t3 = CGAL::Mesh_complex_3_in_triangulation_3<Tr, MeshDomain::Corner_index, MeshDomain::Curve_index>;
  using Criteria = MesherCriteria<Tr>;
};
}
