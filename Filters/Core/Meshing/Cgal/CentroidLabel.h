// SPDX-License-Identifier: GPL-3.0-or-later
// Private to the mesher (includes CGAL): which cells outside the complex the output may take by
// their centroid (toTetMesh, where they hold a constrained piece no cell of the complex holds).
#pragma once

#include "HierarchicalOracle.h"
#include "MeshQuality.h"
#include "OracleMeshDomain.h"

#include <algorithm>

namespace omesh::cgal
{
/// The subdomain index the output gives cell `c` of the triangulation when it lies outside the
/// complex: its centroid's when every vertex lies on an interface or feature line, it is not flat
/// (four points of one face hold no volume) and the centroid lies in a material; else 0 (not taken).
/// Mesh_3's cell level asks only the cells of the complex, so the label rule
/// (MaterialCellCriterion::labelQuality) never sees these: at a part's acute edge on the outer
/// boundary the cells from one face to the other have their circumcentres outside, and the edge
/// was no edge of any output tetrahedron (an 18.4-degree wedge alone: 384 pieces split to the
/// floor and still missing, -2.2 % of its volume).
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
}
