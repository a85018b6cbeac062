// SPDX-License-Identifier: GPL-3.0-or-later
// PRIVATE (includes CGAL): the visitor of the mesher's cell criteria (MesherCriteria3.h).
#pragma once

#include <CGAL/Mesh_3/mesh_standard_criteria.h>

namespace omesh::cgal
{
/// Asks each cell criterion in turn, as CGAL's Criterion_visitor does. CGAL's default visitor
/// (Cell_criteria_visitor_with_features) first sorts a cell's weighted vertices with four filtered
/// predicates (interval arithmetic) for its own size and radius-edge criteria, which the mesher
/// does not add (MaterialCellCriterion handles protecting balls itself); any other criterion it
/// visits exactly as this one does. That sorting costs ~0.7k instructions a tetrahedron of a
/// coarse label map's refinement.
template <class Tr>
class CellCriteriaVisitor : public CGAL::Mesh_3::Criterion_visitor<Tr, typename Tr::Cell_handle>
{
  using Base = CGAL::Mesh_3::Criterion_visitor<Tr, typename Tr::Cell_handle>;

public:
  using Criterion = CGAL::Mesh_3::Abstract_criterion<Tr, CellCriteriaVisitor>;
  using Cell_quality = typename Base::Quality;
  using Is_cell_bad = typename Base::Is_bad;

  CellCriteriaVisitor(const Tr& tr, const typename Tr::Cell_handle& cell)
    : Base(tr, cell)
  {
  }

  void visit(const Criterion& criterion) { Base::do_visit(criterion); }
};
}
