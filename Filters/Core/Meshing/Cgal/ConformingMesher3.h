// SPDX-License-Identifier: GPL-3.0-or-later
// Private to the mesher (includes CGAL). CGAL's Mesher_3 with one more level below the facets:
// the constrained segments (SegmentRefinementLevel). Mirrors Mesh_3::Mesher_3 of CGAL 5.5
// (sequential), whose chain is fixed to Null_mesher_level below the facets.
#pragma once

#include "SegmentRefinementLevel.h"
#include "SliverAvoidingPoint.h"

#include <algorithm>
#include <functional>
#include <iterator>
#include <set>
#include <utility>
#include <vector>

#include <CGAL/Mesh_3/Mesher_3.h>
#include <CGAL/Mesh_3/Refine_cells_3.h>
#include <CGAL/Mesh_3/Refine_facets_3.h>
#include <CGAL/Mesh_3/Refine_facets_manifold_base.h>
#include <CGAL/Mesh_3/Refine_tets_visitor.h>
#include <CGAL/Mesher_level_visitors.h>

namespace omesh
{
namespace cgal
{
/// The facet level as seen by the cell level: a cell refinement point is first tested against
/// the segments (T3.1), then against the restricted facets (T3.2) as in CGAL.
template <class FacetsLevel, class SegmentLevel>
class FacetsLevelWithSegments : public FacetsLevel
{
public:
  template <class Tr, class... Args>
  explicit FacetsLevelWithSegments(SegmentLevel& segments, Tr& tr, Args&&... args)
    : FacetsLevel(tr, std::forward<Args>(args)...)
    , segments_(segments)
    , vertices_([&tr] { return tr.number_of_vertices(); })
  {
  }

  /// T3.2 can cycle: the cell's point encroaches a restricted facet, which is queued; the facet's
  /// own point lies in the ball of a sub-segment too short to split and is dropped (T2.1), nothing
  /// is inserted, and the cell asks again with the same point, forever (seen as "refinement
  /// stalled" on noisy feature networks). The same point asking again with no vertex inserted
  /// since is dropped instead: the cell stays as it is.
  template <class P, class Z>
  CGAL::Mesher_level_conflict_status test_point_conflict_from_superior(const P& p, Z& zone)
  {
    const auto r = segments_.test_point_conflict_from_superior(p, zone);
    if (r != CGAL::NO_CONFLICT)
      return r;
    const auto f = FacetsLevel::test_point_conflict_from_superior(p, zone);
    if (f != CGAL::CONFLICT_BUT_ELEMENT_CAN_BE_RECONSIDERED)
      return f;
    const size_t vertices = vertices_();
    if (p == lastPoint_ && vertices == lastVertices_)
    {
      ++segments_.counters().cyclesBroken;
      return CGAL::CONFLICT_AND_ELEMENT_SHOULD_BE_DROPPED;
    }
    lastPoint_ = p;
    lastVertices_ = vertices;
    return f;
  }

  /// The restricted facets among the facets of the cells incident to `vertices`, treated as the
  /// full scan treats every facet (set in the complex, queued when bad).
  template <class Vertices>
  void scanFacetsAround(const Vertices& vertices)
  {
    auto& tr = this->triangulation_ref_impl();
    std::set<std::pair<typename SegmentLevel::Tr::Cell_handle, int>> seen;
    std::vector<typename SegmentLevel::Tr::Cell_handle> cells;
    for (const auto& v : vertices)
    {
      cells.clear();
      tr.incident_cells(v, std::back_inserter(cells));
      for (const auto& c : cells)
        for (int i = 0; i < 4; ++i)
        {
          typename SegmentLevel::Tr::Facet f(c, i);
          const auto m = tr.mirror_facet(f);
          if (tr.is_infinite(f) || !seen.insert(std::min(std::make_pair(c, i), std::make_pair(m.first, m.second))).second)
            continue;
          this->treat_new_facet(f);
        }
    }
  }

private:
  SegmentLevel& segments_;
  std::function<size_t()> vertices_;
  typename SegmentLevel::Weighted_point lastPoint_;
  size_t lastVertices_ = 0;
};

/// CGAL's cell level whose refinement point may come from the picking region around the
/// circumcentre (SliverAvoidingPoint). CGAL 5.5 takes the circumcentre in a non-virtual CRTP
/// call, so one step of this level is Mesher_level::try_to_refine_element again with the point
/// picked: the same conflict tests (T3.1 / T3.2 through the facet level) on whatever point is chosen.
template <class CellsBase, class Domain>
class PickingCellsLevel : public CellsBase
{
public:
  using Tr = typename CellsBase::Triangulation;
  using Picker = SliverAvoidingPoint<Tr, Domain>;
  using CellsBase::CellsBase;

  void setPicker(Picker* picker) { picker_ = picker; }

  /// As Mesher_level::one_step, the previous (facet) level first.
  template <class Visitor, class Previous>
  void one_step(Visitor visitor, Previous& previous)
  {
    if (!picker_ || !picker_->active())
      CellsBase::one_step(visitor);
    else if (!previous.is_algorithm_done())
      previous.one_step(visitor.previous_level());
    else if (!this->no_longer_element_to_refine())
    {
      const typename Tr::Cell_handle cell = this->get_next_element();
      if (tryToRefine(cell, visitor) == CGAL::CONFLICT_AND_ELEMENT_SHOULD_BE_DROPPED)
        this->pop_next_element();
    }
  }

private:
  template <class Visitor>
  CGAL::Mesher_level_conflict_status tryToRefine(typename Tr::Cell_handle cell, Visitor visitor)
  {
    const Tr& tr = this->triangulation_ref_impl();
    const typename Tr::Bare_point centre = this->refinement_point(cell); // also the new vertex's index
    const typename Tr::Weighted_point p =
      tr.geom_traits().construct_weighted_point_3_object()(picker_->pick(cell, centre));
    this->before_conflicts(cell, p, visitor);
    bool facetInZone = true;
    typename CellsBase::Zone zone = this->conflicts_zone(p, cell, facetInZone);
    const CGAL::Mesher_level_conflict_status result = this->test_point_conflict(p, zone);
    if (result == CGAL::NO_CONFLICT)
    {
      this->before_insertion(cell, p, zone, visitor);
      const typename Tr::Vertex_handle v = this->insert(p, zone);
      this->after_insertion(v, visitor);
    }
    else
      this->after_no_insertion(cell, p, zone, visitor);
    return result;
  }

  Picker* picker_ = nullptr;
};

template <class C3t3, class Criteria, class MeshDomain>
class ConformingMesher3
{
public:
  using Tr = typename C3t3::Triangulation;
  using Segments = SegmentRefinementLevel<C3t3>;
  using FacetsBase = CGAL::Mesh_3::Refine_facets_3<Tr, typename Criteria::Facet_criteria, MeshDomain, C3t3,
    Segments, CGAL::Sequential_tag, CGAL::Mesh_3::Refine_facets_manifold_base>;
  using Facets = FacetsLevelWithSegments<FacetsBase, Segments>;
  using Cells = PickingCellsLevel<CGAL::Mesh_3::Refine_cells_3<Tr, typename Criteria::Cell_criteria, MeshDomain,
                                   C3t3, Facets, CGAL::Sequential_tag>,
    MeshDomain>;
  using SegmentsVisitor = typename Segments::Visitor;
  using FacetsVisitor = CGAL::Mesh_3::tets::Refine_facets_visitor<Tr, Cells, SegmentsVisitor>;
  using CellsVisitor = CGAL::Null_mesh_visitor_level<FacetsVisitor>;

  ConformingMesher3(C3t3& c3t3, const MeshDomain& domain, const Criteria& criteria, Segments& segments, int topology,
    const PickingRegion& picking = PickingRegion())
    : segments_(segments)
    , facets_(segments, c3t3.triangulation(), criteria.facet_criteria_object(), domain, segments, c3t3, topology,
        std::size_t(0), nullptr)
    , cells_(c3t3.triangulation(), criteria.cell_criteria_object(), domain, facets_, c3t3, std::size_t(0), nullptr)
    , facetsVisitor_(&cells_, &segmentsVisitor_)
    , cellsVisitor_(facetsVisitor_)
    , picker_(c3t3.triangulation(), domain, picking)
  {
    cells_.setPicker(&picker_);
    // a segment point is inserted as the facet level inserts its points: the facets (and, once
    // cells are refined, the cells) of its conflict zone are updated by their levels
    segmentsVisitor_.before = [this](const typename Tr::Weighted_point& p, typename Segments::Zone& zone) {
      facets_.before_insertion_impl(typename Tr::Facet(), p, zone);
      if (facetsVisitor_.is_active())
        cells_.before_insertion_handle_cells_in_conflict_zone(zone);
    };
    segmentsVisitor_.after = [this](const typename Tr::Vertex_handle& v) {
      facets_.after_insertion_impl(v);
      if (facetsVisitor_.is_active())
        cells_.update_star(v);
    };
  }
  ConformingMesher3(const ConformingMesher3&) = delete;
  ConformingMesher3& operator=(const ConformingMesher3&) = delete;

  /// The first scan looks only at the facets and cells around `vertices` (the rest of the complex
  /// is known to meet the criteria: after the parallel phase of Conforming); empty: everything.
  /// `badCells`: cells queued as they are (the cells a parallel refinement left bad, found by a
  /// scan of the complex: the cells around them are known to be good).
  void restrictFirstScanTo(
    std::vector<typename Tr::Vertex_handle> vertices, std::vector<typename Tr::Cell_handle> badCells = {})
  {
    region_ = std::move(vertices);
    badCells_ = std::move(badCells);
  }

  void initialize()
  {
    segments_.queueAll();
    if (!region_.empty() || !badCells_.empty())
    {
      // the surface's edges and vertices were scanned before; the cells are looked at from the
      // start (insertions update them through the visitor as in CGAL's cell stage)
      facetsVisitor_.activate();
      if (!region_.empty())
        facets_.scanFacetsAround(region_);
      for (const auto& v : region_)
        cells_.update_star(v);
      for (const auto& c : badCells_)
        cells_.treat_new_cell(c);
      stage_ = Stage::All;
      return;
    }
    facets_.scan_triangulation();
    stage_ = Stage::Facets;
  }

  /// As Mesher_3::one_step: facets (and segments below them) first, then cells.
  void one_step()
  {
    if (!facetsVisitor_.is_active())
    {
      facets_.one_step(facetsVisitor_);
      if (facets_.is_algorithm_done())
      {
        switch (stage_)
        {
          case Stage::Facets:
            facets_.scan_edges();
            stage_ = Stage::FacetsAndEdges;
            if (!facets_.is_algorithm_done())
              break;
            [[fallthrough]];
          case Stage::FacetsAndEdges:
            facets_.scan_vertices();
            stage_ = Stage::FacetsEdgesAndVertices;
            if (!facets_.is_algorithm_done())
              break;
            [[fallthrough]];
          default:
            facetsVisitor_.activate();
            cells_.scan_triangulation();
            stage_ = Stage::All;
        }
      }
    }
    else
      cells_.one_step(cellsVisitor_, facets_);
  }

  const PickingRegion::Counters& pickingCounters() const { return picker_.counters(); }

  /// Not before the cells were scanned: on a complex whose facets are all good already (a second
  /// round, the tail after a parallel refinement) the cells' queue is empty until then.
  bool is_algorithm_done() { return stage_ == Stage::All && cells_.is_algorithm_done(); }

  /// After an interruption: the cells of the complex, if cell refinement had not started.
  void fix_c3t3()
  {
    if (!facetsVisitor_.is_active())
      cells_.scan_triangulation();
  }

private:
  enum class Stage
  {
    Facets,
    FacetsAndEdges,
    FacetsEdgesAndVertices,
    All
  };
  Segments& segments_;
  Facets facets_;
  Cells cells_;
  SegmentsVisitor segmentsVisitor_;
  FacetsVisitor facetsVisitor_;
  CellsVisitor cellsVisitor_;
  typename Cells::Picker picker_;
  Stage stage_ = Stage::Facets;
  std::vector<typename Tr::Vertex_handle> region_;
  std::vector<typename Tr::Cell_handle> badCells_;
};
}
}
