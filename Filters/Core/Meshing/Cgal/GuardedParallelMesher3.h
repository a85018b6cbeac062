// SPDX-License-Identifier: GPL-3.0-or-later
// Private to the mesher (includes CGAL). CGAL's parallel Mesher_3 (Parallel_tag) with a read-only
// level below the facets (ParallelGuardLevel: repeated vertices, the constrained segments' balls):
// every parallel refinement. Mirrors Mesh_3::Mesher_3::refine_mesh of CGAL 5.5 (parallel branch),
// whose chain is fixed to Null_mesher_level below the facets.
#pragma once

#include "ParallelGuardLevel.h"

#include <CGAL/Mesh_3/Mesher_3.h>
#include <CGAL/Mesh_3/Refine_cells_3.h>
#include <CGAL/Mesh_3/Refine_facets_3.h>
#include <CGAL/Mesh_3/Refine_facets_manifold_base.h>
#include <CGAL/Mesh_3/Refine_tets_visitor.h>
#include <CGAL/Mesher_level_visitors.h>

#include <atomic>
#include <cstddef>

namespace omesh
{
namespace cgal
{
/// The facet level as seen by the cell level: a cell refinement point is first tested by the
/// guard (a repeated vertex, T3.1), then against the restricted facets as CGAL does (T3.2; its facet level does
/// not ask its previous level for the cells' points). CGAL's facet level refines an encroached
/// facet at once and has the cell try again; when the guard drops that facet's point, the cell
/// would try again forever (the parallel form of the cycle FacetsLevelWithSegments breaks): the
/// cell is dropped too and left to the sequential round.
template <class FacetsLevel>
class FacetsLevelWithGuard : public FacetsLevel
{
public:
  template <class Tr, class... Args>
  explicit FacetsLevelWithGuard(ParallelGuardLevel& guard, Tr& tr, Args&&... args)
    : FacetsLevel(tr, std::forward<Args>(args)...)
    , guard_(guard)
  {
  }

  /// As Refine_facets_3::test_point_conflict_from_superior_impl (parallel) of CGAL 5.5, with the
  /// guard first and a dropped facet dropping the cell.
  template <class P, class Z, class V>
  CGAL::Mesher_level_conflict_status test_point_conflict_from_superior(const P& p, Z& zone, V& visitor)
  {
    const auto r = guard_.test_point_conflict_from_superior(p, zone);
    if (r != CGAL::NO_CONFLICT)
      return r;
    for (auto& f : zone.internal_facets) // restricted facets inside the zone are encroached
      if (this->is_facet_on_surface(f))
        return refineEncroached(f, p, visitor);
    for (auto& f : zone.boundary_facets)
      if (this->is_facet_encroached(f, p))
        return refineEncroached(f, p, visitor);
    return CGAL::NO_CONFLICT;
  }

private:
  template <class F, class P, class V>
  CGAL::Mesher_level_conflict_status refineEncroached(F& facet, const P& p, V& visitor)
  {
    if (!this->is_encroached_facet_refinable(facet))
      return CGAL::CONFLICT_AND_ELEMENT_SHOULD_BE_DROPPED;
    if (this->try_to_refine_element(facet, visitor) == CGAL::CONFLICT_AND_ELEMENT_SHOULD_BE_DROPPED)
    {
      guard_.countDrop(toVec(p.point()));
      return CGAL::CONFLICT_AND_ELEMENT_SHOULD_BE_DROPPED;
    }
    return CGAL::CONFLICT_BUT_ELEMENT_CAN_BE_RECONSIDERED;
  }

private:
  ParallelGuardLevel& guard_;
};

template <class C3t3, class Criteria, class MeshDomain>
class GuardedParallelMesher3 : CGAL::Mesh_3::Mesher_3_base<typename C3t3::Triangulation, CGAL::Parallel_tag>
{
public:
  using Tr = typename C3t3::Triangulation;
  using Base = CGAL::Mesh_3::Mesher_3_base<Tr, CGAL::Parallel_tag>;
  using FacetsBase = CGAL::Mesh_3::Refine_facets_3<Tr, typename Criteria::Facet_criteria, MeshDomain, C3t3,
    ParallelGuardLevel, CGAL::Parallel_tag, CGAL::Mesh_3::Refine_facets_manifold_base>;
  using Facets = FacetsLevelWithGuard<FacetsBase>;
  using Cells =
    CGAL::Mesh_3::Refine_cells_3<Tr, typename Criteria::Cell_criteria, MeshDomain, C3t3, Facets, CGAL::Parallel_tag>;
  using FacetsVisitor = CGAL::Mesh_3::tets::Refine_facets_visitor<Tr, Cells, CGAL::Null_mesh_visitor>;
  using CellsVisitor = CGAL::Null_mesh_visitor_level<FacetsVisitor>;

  GuardedParallelMesher3(C3t3& c3t3, const MeshDomain& domain, const Criteria& criteria, ParallelGuardLevel& guard,
    int topology, std::size_t maximumVertices, std::atomic<bool>* stop)
    : Base(c3t3.bbox(), ::Concurrent_mesher_config::get().locking_grid_num_cells_per_axis)
    , c3t3_(c3t3)
    , domain_(domain)
    , facets_(guard, c3t3.triangulation(), criteria.facet_criteria_object(), domain, guard, c3t3, topology,
        maximumVertices, stop)
    , cells_(c3t3.triangulation(), criteria.cell_criteria_object(), domain, facets_, c3t3, maximumVertices, stop)
    , facetsVisitor_(&cells_, &nullVisitor_)
    , cellsVisitor_(facetsVisitor_)
    , stop_(stop)
  {
    guard.setInfiniteVertex(&*c3t3.triangulation().infinite_vertex());
    facets_.set_lock_ds(this->get_lock_data_structure());
    facets_.set_worksharing_ds(this->get_worksharing_data_structure());
    cells_.set_lock_ds(this->get_lock_data_structure());
    cells_.set_worksharing_ds(this->get_worksharing_data_structure());
    facets_.set_stop_pointer(stop);
    cells_.set_stop_pointer(stop);
  }
  ~GuardedParallelMesher3() { c3t3_.triangulation().set_lock_data_structure(nullptr); }
  GuardedParallelMesher3(const GuardedParallelMesher3&) = delete;
  GuardedParallelMesher3& operator=(const GuardedParallelMesher3&) = delete;

  /// As Mesher_3::refine_mesh (parallel): the facets (edges and vertices of the surface too), then
  /// the cells. The complex already has its far points (the mesher's own).
  void refine()
  {
    Tr& tr = c3t3_.triangulation();
    c3t3_.clear_cells_and_facets_from_c3t3();
    this->set_bbox(domain_.bbox());
    tr.set_lock_data_structure(nullptr); // the scan is not multi-threaded yet
    facets_.scan_triangulation();
    tr.set_lock_data_structure(this->get_lock_data_structure());
    facets_.refine(facetsVisitor_);
    facets_.scan_edges();
    facets_.refine(facetsVisitor_);
    facets_.scan_vertices();
    facets_.refine(facetsVisitor_);
    facetsVisitor_.activate();
    if (stop_ && stop_->load())
      return;
    cells_.scan_triangulation();
    cells_.refine(cellsVisitor_);
  }

private:
  C3t3& c3t3_;
  const MeshDomain& domain_;
  Facets facets_;
  Cells cells_;
  CGAL::Null_mesh_visitor nullVisitor_;
  FacetsVisitor facetsVisitor_;
  CellsVisitor cellsVisitor_;
  std::atomic<bool>* stop_;
};
}
}
