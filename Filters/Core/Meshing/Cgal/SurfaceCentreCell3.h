// SPDX-License-Identifier: GPL-3.0-or-later
// Private to the mesher (includes CGAL): the triangulation's cell, a model of CGAL's MeshCellBase_3
// as CGAL::Compact_mesh_cell_3 is, but holding the surface centres of its facets (a point and an
// index per facet: 144 of that cell's 296 bytes) out of line, in a block allocated the first time
// one is set. Mesh_3 sets them only on the two cells of a facet whose dual meets a surface, a small
// part of the cells; the others hold a null pointer. At a million tetrahedra that is ~130 MB less
// for the same triangulation, the same meshes, and no slower (the centres are read only where set).
//
// The circumcentre cache, the facets' visited bits and the erase counter (the refinement queue's
// safe handles) come from CGAL's own base for its compact cells, in its sequential or concurrent
// form (TDS::Concurrency_tag).
#pragma once

#include <CGAL/Compact_mesh_cell_base_3.h>
#include <CGAL/Mesh_3/config.h>
#include <CGAL/array.h>

#include <array>
#include <memory>
#include <string>

namespace omesh::cgal
{
template <class GT, class SubdomainIndex, class PatchIndex, class IndexT, class TDS>
class SurfaceCentreCell3
  : public CGAL::Compact_mesh_cell_base_3_base<typename GT::Point_3, typename TDS::Concurrency_tag>
{
  using Base = CGAL::Compact_mesh_cell_base_3_base<typename GT::Point_3, typename TDS::Concurrency_tag>;
  using Base::weighted_circumcenter_;

public:
  using Triangulation_data_structure = TDS;
  using Vertex_handle = typename TDS::Vertex_handle;
  using Cell_handle = typename TDS::Cell_handle;
  using Vertex = typename TDS::Vertex;
  using Cell = typename TDS::Cell;
  using TDS_data = typename TDS::Cell_data;
  template <class TDS2>
  struct Rebind_TDS
  {
    using Other = SurfaceCentreCell3<GT, SubdomainIndex, PatchIndex, IndexT, TDS2>;
  };

  using Subdomain_index = SubdomainIndex;
  using Surface_patch_index = PatchIndex;
  using Index = IndexT;
  using Point_3 = typename GT::Point_3;
  using Point = typename GT::Weighted_point_3;
  // no hidden points (Mesh_3's regular triangulations discard them)
  using Point_container = Point*;
  using Point_iterator = Point*;
  using Point_const_iterator = const Point*;
  using Has_timestamp = CGAL::Tag_true;

  // User-provided, and no initialiser for the time stamp: CGAL's Compact_container constructs a
  // cell in a slot whose time stamp (and erase counter) it keeps, and value-initialisation of a
  // defaulted constructor would zero them.
  SurfaceCentreCell3() {}
  SurfaceCentreCell3(const SurfaceCentreCell3& rhs)
    : N(rhs.N)
    , V(rhs.V)
#ifdef CGAL_INTRUSIVE_LIST
    , next_intrusive_(rhs.next_intrusive_)
    , previous_intrusive_(rhs.previous_intrusive_)
#endif
    , time_stamp_(rhs.time_stamp_)
    , patch_(rhs.patch_)
    , centres_(rhs.centres_ ? std::make_unique<Centres>(*rhs.centres_) : nullptr)
    , sliver_value_(rhs.sliver_value_)
    , subdomain_index_(rhs.subdomain_index_)
  {
  }
  SurfaceCentreCell3& operator=(const SurfaceCentreCell3&) = delete;
  SurfaceCentreCell3(Vertex_handle v0, Vertex_handle v1, Vertex_handle v2, Vertex_handle v3)
    : V(CGAL::make_array(v0, v1, v2, v3))
  {
  }
  SurfaceCentreCell3(Vertex_handle v0, Vertex_handle v1, Vertex_handle v2, Vertex_handle v3, Cell_handle n0,
    Cell_handle n1, Cell_handle n2, Cell_handle n3)
    : N(CGAL::make_array(n0, n1, n2, n3))
    , V(CGAL::make_array(v0, v1, v2, v3))
  {
  }
  ~SurfaceCentreCell3() { invalidate_weighted_circumcenter_cache(); }

  // --- TriangulationDSCellBase_3
  Vertex_handle vertex(int i) const { return V[i]; }
  bool has_vertex(Vertex_handle v) const { return position(V, v) < 4; }
  bool has_vertex(Vertex_handle v, int& i) const { return (i = position(V, v)) < 4; }
  int index(Vertex_handle v) const { return position(V, v); } // v is one of them
  Cell_handle neighbor(int i) const { return N[i]; }
  bool has_neighbor(Cell_handle n) const { return position(N, n) < 4; }
  bool has_neighbor(Cell_handle n, int& i) const { return (i = position(N, n)) < 4; }
  int index(Cell_handle n) const { return position(N, n); } // n is one of them
  void set_vertex(int i, Vertex_handle v)
  {
    invalidate_weighted_circumcenter_cache();
    V[i] = v;
  }
  void set_vertices()
  {
    invalidate_weighted_circumcenter_cache();
    V = {};
  }
  void set_vertices(Vertex_handle v0, Vertex_handle v1, Vertex_handle v2, Vertex_handle v3)
  {
    invalidate_weighted_circumcenter_cache();
    V = CGAL::make_array(v0, v1, v2, v3);
  }
  void set_neighbor(int i, Cell_handle n) { N[i] = n; }
  void set_neighbors() { N = {}; }
  void set_neighbors(Cell_handle n0, Cell_handle n1, Cell_handle n2, Cell_handle n3)
  {
    N = CGAL::make_array(n0, n1, n2, n3);
  }
  bool is_valid(bool = false, int = 0) const { return true; }
  // the Compact_container's free list runs through N[0] while the cell is not in use
  void* for_compact_container() const { return N[0].for_compact_container(); }
  void for_compact_container(void* p) { N[0].for_compact_container(p); }
  TDS_data& tds_data() { return tds_data_; }
  const TDS_data& tds_data() const { return tds_data_; }
  Point_iterator hidden_points_begin() const { return hidden_points_end(); }
  Point_iterator hidden_points_end() const { return nullptr; }
  void hide_point(const Point&) const {}
#ifdef CGAL_INTRUSIVE_LIST
  // Mesh_3's optimisers keep lists of cells through these (CGAL/Mesh_3/config.h defines it)
  Cell_handle next_intrusive() const { return next_intrusive_; }
  void set_next_intrusive(Cell_handle c) { next_intrusive_ = c; }
  Cell_handle previous_intrusive() const { return previous_intrusive_; }
  void set_previous_intrusive(Cell_handle c) { previous_intrusive_ = c; }
#endif
  std::size_t time_stamp() const { return time_stamp_; }
  void set_time_stamp(const std::size_t& ts) { time_stamp_ = ts; }

  // --- MeshCellBase_3
  void invalidate_weighted_circumcenter_cache() const
  {
    if (!::internal_tbb::is_null(weighted_circumcenter_))
    {
      ::internal_tbb::delete_circumcenter(weighted_circumcenter_);
      ::internal_tbb::set_weighted_circumcenter(weighted_circumcenter_, nullptr);
    }
  }
  /// Computed once, then kept until a vertex changes (on several threads: the first one kept).
  template <class GT_>
  const Point_3& weighted_circumcenter(const GT_& gt) const
  {
    if (::internal_tbb::is_null(weighted_circumcenter_))
      this->try_to_set_circumcenter(new Point_3(gt.construct_weighted_circumcenter_3_object()(
        V[0]->point(), V[1]->point(), V[2]->point(), V[3]->point())));
    return *weighted_circumcenter_;
  }
  Subdomain_index subdomain_index() const { return subdomain_index_; }
  void set_subdomain_index(const Subdomain_index& index) { subdomain_index_ = index; }
  void set_sliver_value(double value)
  {
    sliver_cache_validity_ = true;
    sliver_value_ = value;
  }
  double sliver_value() const { return sliver_value_; }
  bool is_cache_valid() const { return sliver_cache_validity_; }
  void reset_cache_validity() const { sliver_cache_validity_ = false; }
  void set_surface_patch_index(int facet, const Surface_patch_index& index) { patch_[facet] = index; }
  Surface_patch_index surface_patch_index(int facet) const { return patch_[facet]; }
  bool is_facet_on_surface(int facet) const { return !(Surface_patch_index() == patch_[facet]); }
  void set_facet_surface_center(int facet, const Point_3& point) { centres().point[facet] = point; }
  /// The origin where no centre was set (CGAL's cell leaves that value undefined).
  Point_3 get_facet_surface_center(int facet) const
  {
    return centres_ ? centres_->point[facet] : Point_3(CGAL::ORIGIN);
  }
  void set_facet_surface_center_index(int facet, const Index& index) { centres().index[facet] = index; }
  Index get_facet_surface_center_index(int facet) const { return centres_ ? centres_->index[facet] : Index(); }
  /// Whether the block of surface centres was allocated (a centre was set on one of its facets).
  bool holds_surface_centres() const { return centres_ != nullptr; }
  static std::string io_signature() { return "SurfaceCentreCell3"; }

private:
  /// Where h is among the four (4: not there).
  template <class Handle>
  static int position(const std::array<Handle, 4>& a, const Handle& h)
  {
    int i = 0;
    while (i < 4 && a[i] != h)
      ++i;
    return i;
  }

  struct Centres
  {
    std::array<Point_3, 4> point;
    std::array<Index, 4> index;
  };
  Centres& centres()
  {
    if (!centres_)
      centres_ = std::make_unique<Centres>(Centres{ { Point_3(CGAL::ORIGIN), Point_3(CGAL::ORIGIN),
        Point_3(CGAL::ORIGIN), Point_3(CGAL::ORIGIN) }, {} });
    return *centres_;
  }

  std::array<Cell_handle, 4> N;
  std::array<Vertex_handle, 4> V;
#ifdef CGAL_INTRUSIVE_LIST
  Cell_handle next_intrusive_ = {}, previous_intrusive_ = {};
#endif
  std::size_t time_stamp_;
  std::array<Surface_patch_index, 4> patch_ = {};
  std::unique_ptr<Centres> centres_;
  double sliver_value_ = 0.0;
  Subdomain_index subdomain_index_ = {};
  TDS_data tds_data_;
  mutable bool sliver_cache_validity_ = false;
};

/// The cell base to give CGAL's Triangulation_data_structure_3 (as
/// CGAL::Compact_mesh_cell_generator_3 for CGAL's cell).
template <class GT, class SubdomainIndex, class PatchIndex, class IndexT>
struct SurfaceCentreCellGenerator3
{
  using Triangulation_data_structure = CGAL::internal::Dummy_tds_3;
  using Vertex_handle = Triangulation_data_structure::Vertex_handle;
  using Cell_handle = Triangulation_data_structure::Cell_handle;
  template <class TDS2>
  struct Rebind_TDS
  {
    using Other = SurfaceCentreCell3<GT, SubdomainIndex, PatchIndex, IndexT, TDS2>;
  };
};
}
