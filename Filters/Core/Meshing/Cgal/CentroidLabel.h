// SPDX-License-Identifier: GPL-3.0-or-later
// Private to the mesher (includes CGAL): cells labelled by their centroid: which cells outside the
// complex the output may take (toTetMesh, where they hold a constrained piece no cell of the
// complex holds), and the cells of the complex the optimisers left across a boundary.
#pragma once

#include "HierarchicalOracle.h"
#include "MeshQuality.h"
#include "MeshValidity.h"
#include "OracleMeshDomain.h"

#include <algorithm>
#include <functional>
#include <utility>
#include <vector>

namespace omesh::cgal
{
/// The subdomain index the output gives cell `c` of the triangulation when it lies outside the
/// complex: its centroid's when every vertex lies on an interface or feature line, it is not flat
/// (four points of one face hold no volume) and the centroid lies in a material; else 0 (not taken).
/// Mesh_3's cell level asks only the cells of the complex, so the label rule
/// (MaterialCellCriterion::labelQuality) never sees these: at a part's acute edge on the outer
/// boundary the cells from one face to the other have their circumcentres outside, and the edge
/// would be no edge of any output tetrahedron (on an 18.4-degree wedge alone, hundreds of pieces
/// split to the floor and still missing, 2 % of its volume lost).
template <class C3t3>
int subdomainByCentroid(const C3t3& c3t3, const typename C3t3::Triangulation::Cell_handle& c, const HierarchicalOracle& oracle)
{
  if (c3t3.triangulation().is_infinite(c) || c3t3.is_in_complex(c))
    return 0;
  for (int i = 0; i < 4; ++i)
  {
    const int dim = c3t3.in_dimension(c->vertex(i));
    if (dim < 0 || dim >= 3)
      return 0;
  }
  const Vec3 a = toVec(c->vertex(0)->point().point()), b = toVec(c->vertex(1)->point().point()),
             d = toVec(c->vertex(2)->point().point()), e = toVec(c->vertex(3)->point().point());
  const double longest = std::max({ norm(b - a), norm(d - a), norm(e - a), norm(d - b), norm(e - b), norm(e - d) });
  if (!(smallestAltitude(a, b, d, e) > 1e-6 * longest))
    return 0;
  const int material = oracle.material(0.25 * (a + b + d + e));
  return material == kOutside ? 0 : subdomainOf(material);
}

/// After the optimisers: every cell of the complex that reaches across a boundary by the label
/// rule (acrossBoundaryBy: each vertex on an interface or feature line, the centroid and the points
/// half way to the vertices in another material, the cell thicker than the finer facet distance)
/// takes the material it lies in, and its faces join or leave the interfaces accordingly. The
/// exuder gives a cell it creates the material of the cell it replaced across the same outer face
/// (CGAL's Slivers_exuder), not the one the cell lies in: on the demo a cell spanning a convex edge
/// of the implant's stem, every point of it inside the implant, came out as cancellous bone. The
/// refinement's label rule (MaterialCellCriterion::labelQuality) refines such cells, but no
/// refinement follows the optimisers; a new label moves no vertex and changes no edge. Cells whose
/// centroid lies outside every material are left (taking them out of the complex could leave
/// vertices no tetrahedron uses). Returns the cells relabelled.
template <class C3t3>
std::size_t relabelCellsAcrossBoundaries(
  C3t3& c3t3, const HierarchicalOracle& oracle, const std::function<double(int)>& facetDistanceOf)
{
  using Cell_handle = typename C3t3::Triangulation::Cell_handle;
  using Patch = typename C3t3::Surface_patch_index;
  const auto& tr = c3t3.triangulation();
  const auto materialAt = [&oracle](const Vec3& x) { return oracle.material(x); };
  std::vector<std::pair<Cell_handle, int>> relabel;
  for (auto c = c3t3.cells_in_complex_begin(); c != c3t3.cells_in_complex_end(); ++c)
  {
    bool onInterfaces = true; // as the validity check counts them (no dimension: inside)
    for (int i = 0; i < 4 && onInterfaces; ++i)
    {
      const int dim = c3t3.in_dimension(c->vertex(i));
      onInterfaces = dim >= 0 && dim < 3;
    }
    if (!onInterfaces)
      continue;
    const Vec3 a = toVec(c->vertex(0)->point().point()), b = toVec(c->vertex(1)->point().point()),
               d = toVec(c->vertex(2)->point().point()), e = toVec(c->vertex(3)->point().point());
    const int own = materialOf(static_cast<int>(c3t3.subdomain_index(c)));
    if (acrossBoundaryBy(a, b, d, e, own, facetDistanceOf, materialAt) > 0)
    {
      const int there = oracle.material(0.25 * (a + b + d + e));
      if (there != kOutside)
        relabel.emplace_back(c, subdomainOf(there));
    }
  }
  for (const auto& [c, index] : relabel)
    c3t3.set_subdomain_index(c, index);
  auto subdomain = [&](Cell_handle c) {
    return tr.is_infinite(c) || !c3t3.is_in_complex(c) ? 0 : static_cast<int>(c3t3.subdomain_index(c));
  };
  for (const auto& [c, index] : relabel)
    for (int i = 0; i < 4; ++i)
    {
      const int beyond = subdomain(c->neighbor(i));
      c3t3.remove_from_complex(c, i);
      if (beyond != index)
        c3t3.add_to_complex(c, i, Patch(std::min(index, beyond), std::max(index, beyond)));
    }
  return relabel.size();
}
}

