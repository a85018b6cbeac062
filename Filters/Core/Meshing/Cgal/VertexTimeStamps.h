// SPDX-License-Identifier: GPL-3.0-or-later
// Private to the mesher's CGAL glue (Meshing/Cgal): numbering Mesh_3 vertices by time stamp.
#pragma once

#include <algorithm>
#include <cstddef>

namespace omesh::cgal
{
/// One more than the largest time stamp of the triangulation's finite vertices. Mesh_3 vertices
/// carry a time stamp unique among all vertices ever created, so arrays of this size indexed by it
/// number vertices without a hash map.
template <class Tr>
std::size_t vertexTimeStampBound(const Tr& tr)
{
  std::size_t bound = 0;
  for (auto v = tr.finite_vertices_begin(); v != tr.finite_vertices_end(); ++v)
    bound = std::max(bound, v->time_stamp() + 1);
  return bound;
}
}
