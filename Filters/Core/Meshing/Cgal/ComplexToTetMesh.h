// SPDX-License-Identifier: GPL-3.0-or-later
// Private to Meshing/OracleMesher.cxx (the sequential Mesh_3 translation unit): the complex as
// the output mesh.
#pragma once

#include "CentroidLabel.h"
#include "HierarchicalOracle.h"
#include "SequentialTypes.h"
#include "TetMesh.h"
#include "VertexTimeStamps.h"

#include <CGAL/Spatial_sort_traits_adapter_3.h>
#include <CGAL/hilbert_sort.h>
#include <CGAL/property_map.h>

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

/// Each vertex the output uses, as met in the complex's cells: its point (with its place in this
/// list), time stamp and dimension, read while the cell that uses it is being read (afterwards
/// each read would be a miss somewhere in CGAL's vertex container).
struct UsedVertexList
{
  using Entry = std::pair<K::Point_3, std::size_t>;
  std::vector<Entry> points;
  std::vector<int> stamps;
  std::vector<signed char> dimensions; ///< 0 corner, 1 on a segment, 2 on an interface, 3 inside
};

/// Gives each vertex of `used` an output id (in `ids`, indexed by time stamp), in Hilbert order of
/// the points: neighbours in space get neighbouring ids, so every later pass over the
/// output (the quality step, the validity check, the VTK arrays, the writers) reads memory nearly in
/// order; the complex's own order scatters a tetrahedron's corners across the mesh, and from about
/// a million tetrahedra those passes wait on memory. Writes the points and their dimensions.
inline void numberVerticesSpatially(UsedVertexList& used, std::vector<int>& ids, TetMesh& out)
{
  // the points sorted with their places in the list (not places sorted through a map to the
  // points: each comparison would read a point elsewhere in memory)
  std::vector<UsedVertexList::Entry>& sorted = used.points;
  using Traits = CGAL::Spatial_sort_traits_adapter_3<K, CGAL::First_of_pair_property_map<UsedVertexList::Entry>>;
  if (!sorted.empty()) // the middle policy reads the first point for the bounding box
    CGAL::hilbert_sort(sorted.begin(), sorted.end(), Traits(), CGAL::Hilbert_sort_middle_policy());
  out.points.resize(sorted.size());
  out.pointDimension.resize(sorted.size());
  for (std::size_t k = 0; k < sorted.size(); ++k)
  {
    const std::size_t at = sorted[k].second;
    ids[static_cast<std::size_t>(used.stamps[at])] = static_cast<int>(k);
    out.points[k] = toVec(sorted[k].first);
    out.pointDimension[k] = used.dimensions[at];
  }
}

/// The vertices the output uses, by time stamp (unique, below the number of vertices ever created:
/// an array, not a hash map). Until they are numbered, the output's tetrahedra and triangles hold
/// time stamps.
struct UsedVertices
{
  std::vector<int> ids; ///< by time stamp: -1 unused, then the output id
  UsedVertexList used;

  explicit UsedVertices(const C3t3& c3t3)
    : c3t3_(c3t3)
  {
    const Tr& tr = c3t3.triangulation();
    ids.assign(vertexTimeStampBound(tr), -1);
    used.points.reserve(tr.number_of_vertices());
    used.stamps.reserve(tr.number_of_vertices());
    used.dimensions.reserve(tr.number_of_vertices());
  }
  /// Marks `v` used; its time stamp.
  int stamp(Tr::Vertex_handle v)
  {
    const int stamp = static_cast<int>(v->time_stamp());
    int& at = ids[static_cast<std::size_t>(stamp)];
    if (at < 0)
    {
      at = 0;
      const int dim = c3t3_.in_dimension(v);
      used.points.emplace_back(v->point().point(), used.points.size());
      used.stamps.push_back(stamp);
      used.dimensions.push_back(static_cast<signed char>(dim < 0 ? 3 : dim));
    }
    return stamp;
  }
  /// Numbers the vertices (numberVerticesSpatially) and puts the ids into the output's triangles
  /// in place of the time stamps; the tetrahedra keep theirs (orderTetsByPoints renumbers them
  /// through `ids` as it orders them: one pass, not two).
  void number(TetMesh& out)
  {
    numberVerticesSpatially(used, ids, out);
    for (auto& t : out.interfaceTriangles)
      for (int& v : t)
        v = ids[static_cast<std::size_t>(v)];
  }

private:
  const C3t3& c3t3_;
};

/// Converts the complex to the output mesh: its cells, and the cells outside it that lie inside a
/// material by their centroid (cellsInsideByCentroid); interface triangles are the complex's
/// facets, and around the cells taken the faces between different materials. Points are in
/// Hilbert order (numberVerticesSpatially), tetrahedra in the complex's order with their corners'
/// time stamps, whose output ids go to `stampIds`: the caller orders and renumbers them
/// (orderTetsByPoints with `stampIds`) once the complex is released, so the copy that takes is not
/// on top of the complex at the run's peak. One pass over the complex's cells reads everything it
/// needs of them: at a million tetrahedra each pass over CGAL's cells costs as much as the whole
/// validity check.
inline TetMesh toTetMesh(const C3t3& c3t3, const HierarchicalOracle& oracle, const std::vector<Tr::Cell_handle>& candidates,
  std::vector<int>& stampIds)
{
  TetMesh out;
  const Tr& tr = c3t3.triangulation();
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
  UsedVertices vertices(c3t3);
  auto addTet = [&](Tr::Cell_handle c, int index) {
    out.tets.push_back(
      { vertices.stamp(c->vertex(0)), vertices.stamp(c->vertex(1)), vertices.stamp(c->vertex(2)), vertices.stamp(c->vertex(3)) });
    out.tetMaterial.push_back(materialOf(index));
  };
  auto addTriangle = [&](Tr::Cell_handle c, int i, int first, int second) {
    std::array<int, 3> tri;
    for (int k = 0; k < 3; ++k)
      tri[k] = vertices.stamp(c->vertex((i + 1 + k) & 3));
    out.interfaceTriangles.push_back(tri);
    out.interfaceMaterials.push_back({ materialOf(first), materialOf(second) });
  };
  out.tets.reserve(c3t3.number_of_cells_in_complex() + taken.size());
  out.tetMaterial.reserve(out.tets.capacity());
  // A restricted facet is written once, from a cell of the complex beside it (the lower handle
  // when both are); around the cells taken, below. A facet with no tetrahedron of the complex on
  // either side (a patch between two outside regions, e.g. the cut-away part and the exterior)
  // bounds nothing: kept, its corners would be nodes no element uses, which finite-element codes
  // reject or leave singular.
  std::size_t reached = 0, besideTaken = 0;
  for (auto c = c3t3.cells_in_complex_begin(); c != c3t3.cells_in_complex_end(); ++c)
  {
    addTet(c, c3t3.subdomain_index(c));
    for (int i = 0; i < 4; ++i)
    {
      if (!c->is_facet_on_surface(i))
        continue;
      const Tr::Cell_handle other = c->neighbor(i);
      if (c3t3.is_in_complex(other) && !(Tr::Cell_handle(c) < other))
        continue;
      ++reached;
      if (!takenAt.empty() && takenAt.count(other))
        continue; // around the cells taken: below
      const auto patch = c3t3.surface_patch_index(c, i);
      addTriangle(c, i, patch.first, patch.second);
    }
  }
  for (const auto& [c, index] : taken)
    addTet(c, index);
  for (std::size_t k = 0; k < taken.size(); ++k)
    for (int i = 0; i < 4; ++i)
    {
      const auto [c, index] = taken[k];
      const Tr::Cell_handle other = c->neighbor(i);
      const auto it = takenAt.find(other);
      // the complex's facets between a cell taken and another outside the complex (once per face)
      if (c->is_facet_on_surface(i) && !c3t3.is_in_complex(other) && !(it != takenAt.end() && it->second < k))
        ++besideTaken;
      const int beyond = subdomain(other);
      // once per face: a face between two cells taken is written from the first of them
      if (beyond != index && !(it != takenAt.end() && it->second < k))
        addTriangle(c, i, index, beyond);
    }
  vertices.number(out);
  const std::size_t dangling = c3t3.number_of_facets_in_complex() - reached - besideTaken;
  out.statistics["interface_triangles_without_tetrahedra"] = static_cast<double>(dangling);
  out.statistics["output.cells_inside_by_centroid"] = static_cast<double>(taken.size());
  stampIds = std::move(vertices.ids);
  return out;
}
}
