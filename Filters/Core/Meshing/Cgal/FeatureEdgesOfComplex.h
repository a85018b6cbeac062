// SPDX-License-Identifier: GPL-3.0-or-later
// Private to the mesher (includes CGAL through the complex types it is given).
#pragma once

#include <iterator>
#include <vector>

namespace omesh::cgal
{
/// Calls f(v, w, curve) once for each feature edge vw of `c3t3`'s complex. Feature edges join
/// vertices on curves (dimension <= 1): only their neighbours are looked at, not every edge of the
/// triangulation (CGAL's edges_in_complex filters them all: half of a complex copy's time).
template <class C3t3, class F>
void forEachFeatureEdge(const C3t3& c3t3, F&& f)
{
  if (c3t3.number_of_edges_in_complex() == 0)
    return;
  const auto& tr = c3t3.triangulation();
  std::vector<typename C3t3::Triangulation::Vertex_handle> around;
  for (auto v = tr.finite_vertices_begin(); v != tr.finite_vertices_end(); ++v)
  {
    if (v->in_dimension() < 0 || v->in_dimension() > 1)
      continue;
    around.clear();
    tr.finite_adjacent_vertices(v, std::back_inserter(around));
    for (const auto& w : around)
      if (&*v < &*w && c3t3.is_in_complex(v, w))
        f(typename C3t3::Triangulation::Vertex_handle(v), w, c3t3.curve_index(v, w));
  }
}
}
