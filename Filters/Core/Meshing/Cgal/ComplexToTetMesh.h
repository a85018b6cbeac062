// SPDX-License-Identifier: GPL-3.0-or-later
// Private to Meshing/OracleMesher.cxx (the sequential Mesh_3 translation unit): the complex as
// the output mesh.
#pragma once

#include "CentroidLabel.h"
#include "HierarchicalOracle.h"
#include "SequentialTypes.h"
#include "TetMesh.h"

#include <algorithm>
#include <unordered_map>
#include <utility>
#include <vector>

namespace omesh::cgal::sequential
{
/// The cells outside the complex that the output takes: of `candidates` (the cells around the
/// constrained sub-segments no cell of the complex holds, SegmentState), those subdomainByCentroid
/// gives a material. A last resort where the segment level split such a piece to its floor and it
/// stayed out. Not every cell subdomainByCentroid gives a material: on the demo 2,945 cells, 2,708
/// of them thin ones along the bone's outer surface and the resection's rim (373 mm3 in all, min
/// dihedral 0.03 degrees, never optimised); nor those reaching across by more than their facet
/// distance (250 cells, 68 mm3, 0.14 degrees): volume at an acute edge on the outer boundary stays
/// a known gap (docs/MESHER.md).
inline std::vector<std::pair<Tr::Cell_handle, int>> cellsInsideByCentroid(
  const C3t3& c3t3, const HierarchicalOracle& oracle, const std::vector<Tr::Cell_handle>& candidates)
{
  std::vector<std::pair<Tr::Cell_handle, int>> taken;
  for (const Tr::Cell_handle& c : candidates)
    if (const int index = subdomainByCentroid(c3t3, c, oracle))
      taken.emplace_back(c, index);
  return taken;
}

/// Converts the complex to the output mesh: its cells, and the cells outside it that lie inside a
/// material by their centroid (cellsInsideByCentroid); interface triangles are the complex's
/// facets, and around the cells taken the faces between different materials.
inline TetMesh toTetMesh(const C3t3& c3t3, const HierarchicalOracle& oracle, const std::vector<Tr::Cell_handle>& candidates)
{
  TetMesh out;
  const Tr& tr = c3t3.triangulation();
  // Output ids in the order the cells first use the vertices, looked up by the vertices' time
  // stamps (unique, below the number of vertices ever created): an array, not a hash map.
  std::size_t stamps = 0;
  for (auto v = tr.finite_vertices_begin(); v != tr.finite_vertices_end(); ++v)
    stamps = std::max(stamps, v->time_stamp() + 1);
  std::vector<int> ids(stamps, -1);
  out.points.reserve(tr.number_of_vertices());
  out.pointDimension.reserve(tr.number_of_vertices());
  auto id = [&](Tr::Vertex_handle v) {
    int& at = ids[v->time_stamp()];
    if (at < 0)
    {
      at = static_cast<int>(out.points.size());
      out.points.push_back(toVec(v->point().point()));
      const int dim = c3t3.in_dimension(v);
      out.pointDimension.push_back(dim < 0 ? 3 : dim);
    }
    return at;
  };
  const std::vector<std::pair<Tr::Cell_handle, int>> taken = cellsInsideByCentroid(c3t3, oracle, candidates);
  std::unordered_map<Tr::Cell_handle, std::size_t> takenAt; // position in `taken`
  for (std::size_t k = 0; k < taken.size(); ++k)
    takenAt.emplace(taken[k].first, k);
  auto subdomain = [&](Tr::Cell_handle c) {
    if (tr.is_infinite(c))
      return 0;
    if (c3t3.is_in_complex(c))
      return static_cast<int>(c3t3.subdomain_index(c));
    const auto it = takenAt.find(c);
    return it == takenAt.end() ? 0 : taken[it->second].second;
  };
  auto addTet = [&](Tr::Cell_handle c, int index) {
    out.tets.push_back({ id(c->vertex(0)), id(c->vertex(1)), id(c->vertex(2)), id(c->vertex(3)) });
    out.tetMaterial.push_back(materialOf(index));
  };
  out.tets.reserve(c3t3.number_of_cells_in_complex() + taken.size());
  out.tetMaterial.reserve(out.tets.capacity());
  for (auto c = c3t3.cells_in_complex_begin(); c != c3t3.cells_in_complex_end(); ++c)
    addTet(c, c3t3.subdomain_index(c));
  for (const auto& [c, index] : taken)
    addTet(c, index);
  auto addTriangle = [&](Tr::Cell_handle c, int i, int first, int second) {
    std::array<int, 3> tri;
    for (int k = 0; k < 3; ++k)
      tri[k] = id(c->vertex((i + 1 + k) & 3));
    out.interfaceTriangles.push_back(tri);
    out.interfaceMaterials.push_back({ materialOf(first), materialOf(second) });
  };
  std::size_t dangling = 0;
  for (auto f = c3t3.facets_in_complex_begin(); f != c3t3.facets_in_complex_end(); ++f)
  {
    const Tr::Cell_handle other = f->first->neighbor(f->second);
    if (!takenAt.empty() && (takenAt.count(f->first) || takenAt.count(other)))
      continue; // around the cells taken: below
    // A restricted facet with no tetrahedron of the complex on either side (a patch between two
    // outside regions, e.g. the cut-away part and the exterior) bounds nothing: kept, its corners
    // would be nodes no element uses, which finite-element codes reject or leave singular.
    if (!c3t3.is_in_complex(f->first) && !c3t3.is_in_complex(other))
    {
      ++dangling;
      continue;
    }
    const auto patch = c3t3.surface_patch_index(*f);
    addTriangle(f->first, f->second, patch.first, patch.second);
  }
  for (std::size_t k = 0; k < taken.size(); ++k)
    for (int i = 0; i < 4; ++i)
    {
      const auto [c, index] = taken[k];
      const Tr::Cell_handle other = c->neighbor(i);
      const int beyond = subdomain(other);
      // once per face: a face between two cells taken is written from the first of them
      const auto it = takenAt.find(other);
      if (beyond != index && !(it != takenAt.end() && it->second < k))
        addTriangle(c, i, index, beyond);
    }
  out.statistics["interface_triangles_without_tetrahedra"] = static_cast<double>(dangling);
  out.statistics["output.cells_inside_by_centroid"] = static_cast<double>(taken.size());
  return out;
}
}
