// SPDX-License-Identifier: GPL-3.0-or-later
// Private to the mesher (includes CGAL). The parallel refinement's complex on its way back into the
// sequential one (ParallelRefinement.cxx), packed into plain arrays so the concurrent triangulation
// can be freed before the sequential one is built: copied directly (copy_tds), both triangulations
// would be alive at once, the peak of a run with threads (twice the sequential run's).
//
// What is kept is what copyComplex copies: the triangulation's vertices and cells with their
// adjacency and Mesh_3 data (vertex dimension, index, ball size; cell subdomain, visited facets, and
// on the surface facets their patch, surface centre and its index), then the complex's corners,
// feature edges and far points. About 40 bytes per cell and 70 per vertex instead of the cells'
// ~300 (circumcentre caches, locks, time stamps). The surface centres of facets off the surface are
// not kept: Mesh_3 reads them only for facets of the complex.
#pragma once

#include "FeatureEdgesOfComplex.h"
#include "WorkerThreads.h"

#include <array>
#include <cstddef>
#include <cstdint>
#include <type_traits>
#include <utility>
#include <vector>

namespace omesh::cgal
{
template <class SrcC3t3, class DstC3t3>
class PackedComplex
{
  static constexpr std::size_t kCellsPerChunk = 8192;

  using SrcTr = typename SrcC3t3::Triangulation;
  using DstTr = typename DstC3t3::Triangulation;
  using SrcVertex = typename SrcTr::Vertex;
  using SrcCell = typename SrcTr::Cell;
  using DstVertex = typename DstTr::Vertex;
  using DstCell = typename DstTr::Cell;
  using WeightedPoint = typename SrcTr::Weighted_point;
  using VertexIndex = std::decay_t<decltype(std::declval<const SrcVertex&>().index())>;
  using BallSize = std::decay_t<decltype(std::declval<const SrcVertex&>().meshing_info())>;
  using SubdomainIndex = typename SrcCell::Subdomain_index;
  using PatchIndex = typename SrcCell::Surface_patch_index;
  using Centre = std::decay_t<decltype(std::declval<const SrcCell&>().get_facet_surface_center(0))>;
  using CentreIndex = std::decay_t<decltype(std::declval<const SrcCell&>().get_facet_surface_center_index(0))>;
  using CornerIndex = typename SrcC3t3::Corner_index;
  using CurveIndex = typename SrcC3t3::Curve_index;

public:
  /// Packs `src`, whose triangulation must have dimension 3. Numbers its vertices and cells in
  /// their time stamps: `src` is only good for being destroyed afterwards.
  explicit PackedComplex(SrcC3t3& src)
  {
    SrcTr& tr = src.triangulation();
    auto& tds = tr.tds();
    std::uint32_t n = 0;
    vertices_.reserve(tds.vertices().size());
    for (auto v = tds.vertices().begin(); v != tds.vertices().end(); ++v)
    {
      v->set_time_stamp(n++);
      vertices_.push_back({ v->point(), v->in_dimension(), v->index(), v->meshing_info(), 0 });
    }
    std::vector<typename SrcTr::Cell_handle> cells;
    cells.reserve(tds.cells().size());
    for (auto c = tds.cells().begin(); c != tds.cells().end(); ++c)
    {
      c->set_time_stamp(cells.size());
      cells.push_back(c);
    }
    for (auto v = tds.vertices().begin(); v != tds.vertices().end(); ++v)
      vertices_[v->time_stamp()].cell = id(v->cell());
    infinite_ = id(tr.infinite_vertex());

    // the cells in chunks on the threads runOnThreads allows (reads only), their surface facets
    // merged in chunk order: the same record on any number of threads
    cells_.resize(cells.size());
    const std::size_t chunks = chunkCount(cells.size(), kCellsPerChunk);
    std::vector<std::vector<SurfaceFacet>> facets(chunks);
    forEachChunk(cells.size(), chunks, [&](std::size_t k, std::size_t begin, std::size_t end) {
      for (std::size_t j = begin; j < end; ++j)
      {
        const auto& c = cells[j];
        PackedCell p{ { id(c->vertex(0)), id(c->vertex(1)), id(c->vertex(2)), id(c->vertex(3)) },
          { id(c->neighbor(0)), id(c->neighbor(1)), id(c->neighbor(2)), id(c->neighbor(3)) }, c->subdomain_index(), 0 };
        for (std::uint8_t i = 0; i < 4; ++i)
        {
          if (c->is_facet_visited(i))
            p.visited |= std::uint8_t(1u << i);
          if (c->surface_patch_index(i) != PatchIndex())
            facets[k].push_back({ static_cast<std::uint32_t>(j), i, c->surface_patch_index(i),
              c->get_facet_surface_center(i), c->get_facet_surface_center_index(i) });
        }
        cells_[j] = p;
      }
    });
    for (const auto& part : facets)
      surfaceFacets_.insert(surfaceFacets_.end(), part.begin(), part.end());

    for (auto v = src.vertices_in_complex_begin(); v != src.vertices_in_complex_end(); ++v)
      corners_.emplace_back(id(v), src.corner_index(v));
    forEachFeatureEdge(src, [this](auto v, auto w, auto curve) { edges_.push_back({ id(v), id(w), curve }); });
  }

  /// Builds the packed complex in `dst` (cleared first). Time stamps are `dst`'s own.
  void unpackInto(DstC3t3& dst) const
  {
    dst.clear();
    DstTr& tr = dst.triangulation();
    auto& tds = tr.tds();
    tds.clear();
    tds.set_dimension(3);
    std::vector<typename DstTr::Vertex_handle> vertex;
    vertex.reserve(vertices_.size());
    for (const PackedVertex& p : vertices_)
    {
      DstVertex v;
      v.set_time_stamp(std::size_t(-1)); // the container gives a new one
      v.set_point(p.point);
      v.set_dimension(p.dimension);
      v.set_index(p.index);
      v.set_meshing_info(p.ballSize);
      vertex.push_back(tds.create_vertex(v));
    }
    std::vector<typename DstTr::Cell_handle> cell;
    cell.reserve(cells_.size());
    for (const PackedCell& p : cells_)
    {
      DstCell c;
      c.set_time_stamp(std::size_t(-1));
      const auto h = tds.create_cell(c);
      for (int i = 0; i < 4; ++i)
      {
        h->set_vertex(i, vertex[p.vertices[i]]);
        if (p.visited & (1u << i))
          h->set_facet_visited(i);
        else
          h->reset_visited(i);
      }
      if (p.subdomain != SubdomainIndex())
        dst.add_to_complex(h, p.subdomain); // counts the complex's cells as a rescan would
      cell.push_back(h);
    }
    forEachChunk(cells_.size(), chunkCount(cells_.size(), kCellsPerChunk), [&](std::size_t, std::size_t begin, std::size_t end) {
      for (std::size_t k = begin; k < end; ++k)
        for (int i = 0; i < 4; ++i)
          cell[k]->set_neighbor(i, cell[cells_[k].neighbours[i]]);
    });
    for (std::size_t k = 0; k < vertices_.size(); ++k)
      vertex[k]->set_cell(cell[vertices_[k].cell]);
    tr.set_infinite_vertex(vertex[infinite_]);
    // Both sides of a facet of the complex are packed: the first one adds it (and its mirror) and
    // counts it, as CGAL's rescan_after_load_of_triangulation would (a pass over every facet).
    for (const SurfaceFacet& f : surfaceFacets_)
    {
      dst.add_to_complex(cell[f.cell], f.facet, f.patch);
      cell[f.cell]->set_facet_surface_center(f.facet, f.centre);
      cell[f.cell]->set_facet_surface_center_index(f.facet, f.centreIndex);
    }

    for (const auto& [v, index] : corners_)
      dst.add_to_complex(vertex[v], index);
    // the rescan's rule for the rest: a vertex of dimension 0 is a corner (index 1)
    for (std::size_t k = 0; k < vertices_.size(); ++k)
      if (vertices_[k].dimension == 0 && !dst.is_in_complex(vertex[k]))
        dst.add_to_complex(vertex[k], CornerIndex(1));
    for (const FeatureEdge& e : edges_)
      dst.add_to_complex(vertex[e.a], vertex[e.b], e.curve);
    for (std::size_t k = 0; k < vertices_.size(); ++k)
      if (vertices_[k].dimension == -1 && k != infinite_)
        dst.add_far_point(vertex[k]);
  }

private:
  template <class Handle>
  static std::uint32_t id(const Handle& h)
  {
    return static_cast<std::uint32_t>(h->time_stamp());
  }

  struct PackedVertex
  {
    WeightedPoint point;
    int dimension;
    VertexIndex index;
    BallSize ballSize;
    std::uint32_t cell;
  };
  struct PackedCell
  {
    std::array<std::uint32_t, 4> vertices, neighbours;
    SubdomainIndex subdomain;
    std::uint8_t visited;
  };
  struct SurfaceFacet
  {
    std::uint32_t cell;
    std::uint8_t facet;
    PatchIndex patch;
    Centre centre;
    CentreIndex centreIndex;
  };
  struct FeatureEdge
  {
    std::uint32_t a, b;
    CurveIndex curve;
  };

  std::vector<PackedVertex> vertices_;
  std::vector<PackedCell> cells_;
  std::vector<SurfaceFacet> surfaceFacets_;
  std::vector<std::pair<std::uint32_t, CornerIndex>> corners_;
  std::vector<FeatureEdge> edges_;
  std::uint32_t infinite_ = 0;
};
}
