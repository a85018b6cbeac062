// SPDX-License-Identifier: GPL-3.0-or-later
// PRIVATE (includes CGAL): the type of the mesher's criteria, sequential and parallel.
#pragma once

#include "CellCriteriaVisitor.h"
#include "FacetCriteriaVisitor.h"

#include <CGAL/Mesh_criteria_3.h>

namespace omesh::cgal
{
/// CGAL's criteria with the mesher's visitors (the same decisions as CGAL's for the criteria the
/// mesher adds: MaterialCriteria3.h and CGAL's facet topology criterion).
template <class Tr>
using MesherCriteria = CGAL::Mesh_criteria_3<Tr, CGAL::Mesh_edge_criteria_3<Tr>,
  CGAL::Mesh_facet_criteria_3<Tr, FacetCriteriaVisitor<Tr>>, CGAL::Mesh_cell_criteria_3<Tr, CellCriteriaVisitor<Tr>>>;
}
