// SPDX-License-Identifier: GPL-3.0-or-later
// Private to the mesher (includes CGAL). A compact record of a mesh complex from which it can be
// rebuilt: the weighted points with their Mesh_3 dimension and index, and the complex's cells,
// facets, edges and corners as vertex numbers. The mesher keeps one across the exuder to undo it
// (SliverOptimisation.h, exudeKeepingSegments): about 16 bytes per tetrahedron instead of a copy of
// the whole triangulation (hundreds of bytes per cell: neighbours, facet surface centres, caches).
//
// Cells: only those next to a wall are recorded (a wall: a facet of the complex, or a facet between
// cells of different subdomains), with the walls among their facets. The others take the label of
// a neighbour across a facet that is no wall, so restore() floods the recorded labels through them.
//
// Why a rebuild gives the same complex: the regular triangulation of a set of weighted points is
// unique (CGAL breaks ties by symbolic perturbation, independently of the insertion order), so
// re-inserting the points gives the same cells, and the recorded labels go back on them. restore()
// counts what it could not put back, which is nothing unless that reasoning fails.
#pragma once

#include "ExactCoordinates.h"
#include "VertexTimeStamps.h"

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <tuple>
#include <unordered_map>
#include <utility>
#include <vector>

namespace omesh
{
namespace cgal
{
template <class C3t3>
class ComplexSnapshot
{
public:
  using Tr = typename C3t3::Triangulation;
  using Vertex_handle = typename Tr::Vertex_handle;
  using Cell_handle = typename Tr::Cell_handle;
  using Weighted_point = typename Tr::Weighted_point;

  /// What restore() could not put back (all zero when the rebuilt triangulation is the recorded one).
  struct Lost
  {
    std::size_t vertices = 0, cells = 0, facets = 0, edges = 0, corners = 0;
    bool any() const { return vertices || cells || facets || edges || corners; }
  };

  /// Records `c3t3`.
  explicit ComplexSnapshot(const C3t3& c3t3)
  {
    const Tr& tr = c3t3.triangulation();
    // vertex numbers: the order of the triangulation's vertices, looked up by time stamp (unique
    // per vertex ever created, so a vector rather than a hash map)
    std::vector<std::uint32_t> number(vertexTimeStampBound(tr), 0);
    vertices_.reserve(tr.number_of_vertices());
    for (auto v = tr.finite_vertices_begin(); v != tr.finite_vertices_end(); ++v)
    {
      number[v->time_stamp()] = static_cast<std::uint32_t>(vertices_.size());
      vertices_.push_back({ tr.point(v), v->in_dimension(), c3t3.index(v) });
    }
    auto id = [&](Vertex_handle v) { return number[v->time_stamp()]; };

    // One pass over the cells (the complex's own iterators would walk them twice); a facet is
    // met from both of its cells and recorded twice until restore() orders the records. On one
    // thread: the record is alive at the exuder's peak, and chunks merged afterwards (or a list
    // of the cells to split) would hold more of it at once.
    cellsInComplex_ = c3t3.number_of_cells_in_complex();
    cells_.reserve(2 * c3t3.number_of_facets_in_complex() + 64); // most walls are facets of the complex
    facets_.reserve(2 * c3t3.number_of_facets_in_complex());
    for (auto c = tr.finite_cells_begin(); c != tr.finite_cells_end(); ++c)
    {
      const bool inComplex = c3t3.is_in_complex(c);
      // a cell of the complex without walls has no facet of the complex either: nothing to record
      const std::uint8_t walls = inComplex ? wallsOf(c3t3, c) : 0;
      if (inComplex ? !walls : !onSurface(c3t3, c))
        continue;
      const std::array<std::uint32_t, 4> ids{ id(c->vertex(0)), id(c->vertex(1)), id(c->vertex(2)), id(c->vertex(3)) };
      if (walls)
        cells_.push_back(CellRecord{ sorted<4>(ids), c3t3.subdomain_index(c), sortedWalls(ids, walls) });
      for (int j = 0; j < 4; ++j)
      {
        if (!c3t3.is_in_complex(c, j))
          continue;
        std::array<std::uint32_t, 3> k{};
        for (int m = 0, n = 0; m < 4; ++m)
          if (m != j)
            k[n++] = ids[m];
        facets_.push_back({ sorted<3>(k), c3t3.surface_patch_index(c, j) });
      }
    }

    // edges_in_complex walks every edge of the triangulation (most of the record's time when it
    // has none, as Conforming's complexes)
    if (c3t3.number_of_edges_in_complex() > 0)
      for (auto e = c3t3.edges_in_complex_begin(); e != c3t3.edges_in_complex_end(); ++e)
        edges_.push_back({ id(e->first->vertex(e->second)), id(e->first->vertex(e->third)), c3t3.curve_index(*e) });
    for (auto v = c3t3.vertices_in_complex_begin(); v != c3t3.vertices_in_complex_end(); ++v)
      corners_.push_back({ id(v), c3t3.corner_index(v) });
  }

  /// Empties `c3t3` (same object: references to it and its triangulation stay valid) and rebuilds
  /// it from the record. Vertex handles into the old triangulation are invalid afterwards.
  Lost restore(C3t3& c3t3)
  {
    orderRecords();
    c3t3.clear();
    Lost lost;
    const Handles h = reinsertVertices(c3t3, lost);
    restoreCellsAndFacets(c3t3, h, lost);
    restoreEdgesAndCorners(c3t3, h, lost);
    // The far points (the mesher's 8 around the box) come back as vertices like the others; the
    // complex's list of them serves only remove_far_points, which nothing calls after refinement.
    return lost;
  }

private:
  /// The cell and facet records ordered for the lookups of restoreCellsAndFacets, each facet once.
  /// Done here, not while recording: most records are never restored.
  void orderRecords()
  {
    std::sort(cells_.begin(), cells_.end(), [](const auto& a, const auto& b) { return a.ids < b.ids; });
    std::sort(facets_.begin(), facets_.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    facets_.erase(std::unique(facets_.begin(), facets_.end(), [](const auto& a, const auto& b) { return a.first == b.first; }),
      facets_.end());
  }

  /// Record number -> new handle (null where a vertex did not come back) and back.
  struct Handles
  {
    std::vector<Vertex_handle> handle;
    std::unordered_map<Vertex_handle, std::uint32_t> idOf;
  };

  Handles reinsertVertices(C3t3& c3t3, Lost& lost) const
  {
    Tr& tr = c3t3.triangulation();
    std::vector<Weighted_point> points;
    points.reserve(vertices_.size());
    for (const VertexRecord& v : vertices_)
      points.push_back(v.point);
    tr.insert(points.begin(), points.end()); // spatially sorted by CGAL
    std::vector<Weighted_point>().swap(points);

    // the new handles in record order, found by their coordinates (no two vertices share them)
    std::unordered_map<ExactCoordinates, std::uint32_t, ExactCoordinatesHash> number;
    number.reserve(vertices_.size());
    for (std::size_t i = 0; i < vertices_.size(); ++i)
      number.emplace(coordinates(vertices_[i].point), static_cast<std::uint32_t>(i));
    std::vector<Vertex_handle> handle(vertices_.size());
    std::unordered_map<Vertex_handle, std::uint32_t> idOf;
    idOf.reserve(vertices_.size());
    for (auto v = tr.finite_vertices_begin(); v != tr.finite_vertices_end(); ++v)
    {
      auto it = number.find(coordinates(tr.point(v)));
      if (it == number.end())
        continue;
      handle[it->second] = v;
      idOf.emplace(v, it->second);
    }
    for (std::size_t i = 0; i < vertices_.size(); ++i)
    {
      if (handle[i] == Vertex_handle())
      {
        ++lost.vertices; // hidden by a heavier neighbour (weights are zero before the exuder)
        continue;
      }
      handle[i]->set_dimension(vertices_[i].dimension);
      c3t3.set_index(handle[i], vertices_[i].index);
    }
    return Handles{ std::move(handle), std::move(idOf) };
  }

  void restoreCellsAndFacets(C3t3& c3t3, const Handles& h, Lost& lost) const
  {
    Tr& tr = c3t3.triangulation();
    const auto& idOf = h.idOf;
    std::size_t facetsFound = 0;
    std::vector<std::pair<Cell_handle, std::uint8_t>> recorded; // with their walls, local indices
    recorded.reserve(cells_.size());
    for (auto c = tr.finite_cells_begin(); c != tr.finite_cells_end(); ++c)
    {
      std::array<std::uint32_t, 4> ids{};
      for (int j = 0; j < 4; ++j)
        ids[j] = idOf.at(c->vertex(j));
      const std::array<std::uint32_t, 4> key = sorted<4>(ids);
      if (const CellRecord* cell = find(cells_, key))
      {
        c3t3.add_to_complex(c, cell->label);
        std::uint8_t walls = 0;
        for (int j = 0; j < 4; ++j)
          if (cell->walls & (1u << (std::find(key.begin(), key.end(), ids[j]) - key.begin())))
            walls |= static_cast<std::uint8_t>(1u << j);
        recorded.emplace_back(c, walls);
      }
      for (int j = 0; j < 4; ++j)
      {
        std::array<std::uint32_t, 3> k{};
        for (int m = 0, n = 0; m < 4; ++m)
          if (m != j)
            k[n++] = ids[m];
        auto facet = find(facets_, sorted<3>(k));
        if (facet && !c3t3.is_in_complex(c, j)) // each facet is met from both of its cells
        {
          c3t3.add_to_complex(c, j, facet->second);
          ++facetsFound;
        }
      }
    }
    const std::size_t labelled = recorded.size() + floodLabels(c3t3, std::move(recorded));
    lost.cells = cellsInComplex_ > labelled ? cellsInComplex_ - labelled : 0;
    lost.facets = facets_.size() - facetsFound;
  }

  /// The recorded cells' labels carried to the cells without a record: across every facet that is
  /// no wall of the cell it leaves (a cell without a record has none), into cells still without a
  /// label. Returns how many cells it labelled.
  static std::size_t floodLabels(C3t3& c3t3, std::vector<std::pair<Cell_handle, std::uint8_t>> front)
  {
    const Tr& tr = c3t3.triangulation();
    std::size_t labelled = 0;
    while (!front.empty())
    {
      const auto [c, walls] = front.back();
      front.pop_back();
      for (int j = 0; j < 4; ++j)
      {
        const Cell_handle n = c->neighbor(j);
        if ((walls & (1u << j)) || tr.is_infinite(n) || c3t3.is_in_complex(n))
          continue;
        c3t3.add_to_complex(n, c3t3.subdomain_index(c));
        ++labelled;
        front.emplace_back(n, 0);
      }
    }
    return labelled;
  }

  void restoreEdgesAndCorners(C3t3& c3t3, const Handles& h, Lost& lost) const
  {
    Tr& tr = c3t3.triangulation();
    const auto& handle = h.handle;
    for (const auto& [a, b, curve] : edges_)
    {
      typename Tr::Cell_handle c;
      int i, j;
      if (handle[a] != Vertex_handle() && handle[b] != Vertex_handle() && tr.is_edge(handle[a], handle[b], c, i, j))
        c3t3.add_to_complex(handle[a], handle[b], curve);
      else
        ++lost.edges;
    }
    for (const auto& [v, corner] : corners_)
    {
      if (handle[v] != Vertex_handle())
        c3t3.add_to_complex(handle[v], corner);
      else
        ++lost.corners;
    }
  }

public:
  /// Bytes held by the record (for the statistics and the benchmarks).
  std::size_t bytes() const
  {
    return vertices_.capacity() * sizeof(VertexRecord) + cells_.capacity() * sizeof(CellRecord) +
      facets_.capacity() * sizeof(facets_[0]) + edges_.capacity() * sizeof(edges_[0]) +
      corners_.capacity() * sizeof(corners_[0]);
  }

private:
  struct VertexRecord
  {
    Weighted_point point;
    int dimension;
    typename C3t3::Index index;
  };
  /// A cell of the complex with the walls among its facets: bit k for the facet opposite its k-th
  /// smallest vertex number.
  struct CellRecord
  {
    std::array<std::uint32_t, 4> ids; ///< sorted
    typename C3t3::Subdomain_index label;
    std::uint8_t walls;
  };
  /// The walls among the facets of `c` (in the complex): bit j for the facet opposite its vertex j.
  static std::uint8_t wallsOf(const C3t3& c3t3, Cell_handle c)
  {
    std::uint8_t walls = 0;
    for (int j = 0; j < 4; ++j)
      if (c3t3.is_in_complex(c, j) || !(c3t3.subdomain_index(c->neighbor(j)) == c3t3.subdomain_index(c)))
        walls |= static_cast<std::uint8_t>(1u << j);
    return walls;
  }
  static bool onSurface(const C3t3& c3t3, Cell_handle c)
  {
    for (int j = 0; j < 4; ++j)
      if (c3t3.is_in_complex(c, j))
        return true;
    return false;
  }
  /// `walls` (bit j: opposite ids[j]) with bit k for the facet opposite the k-th smallest id.
  static std::uint8_t sortedWalls(const std::array<std::uint32_t, 4>& ids, std::uint8_t walls)
  {
    std::uint8_t out = 0;
    for (int j = 0; j < 4; ++j)
      if (walls & (1u << j))
      {
        int rank = 0;
        for (int m = 0; m < 4; ++m)
          rank += ids[m] < ids[j];
        out |= static_cast<std::uint8_t>(1u << rank);
      }
    return out;
  }
  static ExactCoordinates coordinates(const Weighted_point& p) { return exactCoordinates(p.x(), p.y(), p.z()); }
  template <std::size_t N>
  static std::array<std::uint32_t, N> sorted(std::array<std::uint32_t, N> k)
  {
    std::sort(k.begin(), k.end());
    return k;
  }
  /// The vertex numbers a record is ordered and found by.
  static const std::array<std::uint32_t, 4>& keyOf(const CellRecord& r) { return r.ids; }
  template <class Pair>
  static const auto& keyOf(const Pair& p)
  {
    return p.first;
  }
  template <class Entry, std::size_t N>
  static const Entry* find(const std::vector<Entry>& sortedEntries, const std::array<std::uint32_t, N>& key)
  {
    auto it = std::lower_bound(sortedEntries.begin(), sortedEntries.end(), key,
      [](const Entry& e, const std::array<std::uint32_t, N>& k) { return keyOf(e) < k; });
    return it != sortedEntries.end() && keyOf(*it) == key ? &*it : nullptr;
  }

  std::vector<VertexRecord> vertices_;
  std::vector<CellRecord> cells_; ///< the cells next to a wall
  std::size_t cellsInComplex_ = 0;
  std::vector<std::pair<std::array<std::uint32_t, 3>, typename C3t3::Surface_patch_index>> facets_;
  std::vector<std::tuple<std::uint32_t, std::uint32_t, typename C3t3::Curve_index>> edges_;
  std::vector<std::pair<std::uint32_t, typename C3t3::Corner_index>> corners_;
};
}
}
