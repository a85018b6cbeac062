// SPDX-License-Identifier: GPL-3.0-or-later
// Private to the mesher's translation units (includes CGAL): the triangulation and complex types of
// the mesher, sequential (OracleMesher.cxx) or parallel (ParallelRefinement.cxx, CGAL's
// Parallel_tag: concurrent containers and a lock grid). Both share the geometric traits, the vertex
// and cell bases, so a complex can be copied from one to the other (ParallelRefinement.cxx, PackedComplex.h).
#pragma once

#include "OracleMeshDomain.h"

#include <CGAL/Mesh_complex_3_in_triangulation_3.h>
#include <CGAL/Mesh_criteria_3.h>
#include <CGAL/Mesh_domain_with_polyline_features_3.h>
#include <CGAL/Mesh_triangulation_3.h>

#include <algorithm>
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
    const K::Point_3 c = Base::operator()(p, q, r, s, forceExact);
    if (forceExact || (p.weight() == 0 && q.weight() == 0 && r.weight() == 0 && s.weight() == 0))
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
using CellBase = CGAL::Compact_mesh_cell_generator_3<GeomTraits, MeshDomain::Subdomain_index,
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
  using Criteria = CGAL::Mesh_criteria_3<Tr>;
};
}
