// SPDX-License-Identifier: GPL-3.0-or-later
// The only core translation unit that instantiates CGAL's AABB tree and Side_of_triangle_mesh.
#include "SurfaceDomain.h"

#include "InputError.h"

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Surface_mesh.h>

#include <cmath>
#include <cstdint>
#include <deque>

namespace omesh
{
namespace
{
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = K::Point_3;
using Mesh = CGAL::Surface_mesh<Point>;
using SideOf = CGAL::Side_of_triangle_mesh<Mesh, K>;
using Tree = SideOf::AABB_tree;
namespace PMP = CGAL::Polygon_mesh_processing;

Point toCgal(const Vec3& p) { return { p.x, p.y, p.z }; }

enum CellState : uint8_t
{
  kCellOutside = 0,
  kCellInside = 1,
  kCellBoundary = 2,
  kCellUnknown = 3
};
}

struct SurfaceDomain::Impl
{
  Mesh mesh;
  std::unique_ptr<Tree> tree;
  std::unique_ptr<SideOf> side;
  BoundingBox box;
  // Inside/outside/boundary classification of a uniform grid over the box: a query in a cell that
  // no triangle touches takes that cell's answer, every other query goes to the exact test.
  int n[3] = { 1, 1, 1 };
  Vec3 origin, invCell, cell;
  std::vector<uint8_t> state;

  bool exact(const Vec3& p) const { return (*side)(toCgal(p)) != CGAL::ON_UNBOUNDED_SIDE; }
  size_t cellIndex(int i, int j, int k) const
  {
    return static_cast<size_t>(i) + static_cast<size_t>(n[0]) * (static_cast<size_t>(j) + static_cast<size_t>(n[1]) * k);
  }
  void buildGrid(size_t numTriangles);
};

void SurfaceDomain::Impl::buildGrid(size_t numTriangles)
{
  const Vec3 size = box.size();
  const double diag = norm(size);
  // About 8 cells per triangle, between 16^3 and 128^3 cells, cubic-ish cells.
  const double target = std::clamp(8.0 * static_cast<double>(numTriangles), 4096.0, 2097152.0);
  const double volume = std::max(size.x, 1e-3 * diag) * std::max(size.y, 1e-3 * diag) * std::max(size.z, 1e-3 * diag);
  const double h = std::cbrt(volume / target);
  const double pad = 1e-6 * diag;
  origin = box.min - Vec3{ pad, pad, pad };
  for (int a = 0; a < 3; ++a)
  {
    const double extent = size[a] + 2 * pad;
    n[a] = std::clamp(static_cast<int>(std::ceil(extent / h)), 1, 256);
    cell[a] = extent / n[a];
    invCell[a] = 1.0 / cell[a];
  }
  state.assign(static_cast<size_t>(n[0]) * n[1] * n[2], kCellUnknown);

  const double eps = 1e-9 * diag; // cells are tested slightly enlarged: rounding cannot hide a touch
  for (auto f : mesh.faces())
  {
    auto h0 = mesh.halfedge(f);
    const Point& p0 = mesh.point(mesh.target(h0));
    const Point& p1 = mesh.point(mesh.target(mesh.next(h0)));
    const Point& p2 = mesh.point(mesh.source(h0));
    const K::Triangle_3 tri(p0, p1, p2);
    const CGAL::Bbox_3 tb = tri.bbox();
    int lo[3], hi[3];
    for (int a = 0; a < 3; ++a)
    {
      lo[a] = std::clamp(static_cast<int>(std::floor((tb.min(a) - eps - origin[a]) * invCell[a])), 0, n[a] - 1);
      hi[a] = std::clamp(static_cast<int>(std::floor((tb.max(a) + eps - origin[a]) * invCell[a])), 0, n[a] - 1);
    }
    for (int k = lo[2]; k <= hi[2]; ++k)
      for (int j = lo[1]; j <= hi[1]; ++j)
        for (int i = lo[0]; i <= hi[0]; ++i)
        {
          uint8_t& s = state[cellIndex(i, j, k)];
          if (s == kCellBoundary)
            continue;
          const CGAL::Bbox_3 cb(origin.x + i * cell.x - eps, origin.y + j * cell.y - eps,
            origin.z + k * cell.z - eps, origin.x + (i + 1) * cell.x + eps,
            origin.y + (j + 1) * cell.y + eps, origin.z + (k + 1) * cell.z + eps);
          if (CGAL::do_intersect(tri, cb))
            s = kCellBoundary;
        }
  }
  // Face-adjacent cells that no triangle touches lie on the same side: flood-fill each component
  // and classify it with one exact query at a cell centre.
  std::deque<size_t> queue;
  for (size_t seed = 0; seed < state.size(); ++seed)
  {
    if (state[seed] != kCellUnknown)
      continue;
    const int si = static_cast<int>(seed % n[0]);
    const int sj = static_cast<int>((seed / n[0]) % n[1]);
    const int sk = static_cast<int>(seed / (static_cast<size_t>(n[0]) * n[1]));
    const Vec3 centre{ origin.x + (si + 0.5) * cell.x, origin.y + (sj + 0.5) * cell.y, origin.z + (sk + 0.5) * cell.z };
    const uint8_t value = exact(centre) ? kCellInside : kCellOutside;
    state[seed] = value;
    queue.push_back(seed);
    while (!queue.empty())
    {
      const size_t c = queue.front();
      queue.pop_front();
      const int ci = static_cast<int>(c % n[0]);
      const int cj = static_cast<int>((c / n[0]) % n[1]);
      const int ck = static_cast<int>(c / (static_cast<size_t>(n[0]) * n[1]));
      const int nb[6][3] = { { ci - 1, cj, ck }, { ci + 1, cj, ck }, { ci, cj - 1, ck }, { ci, cj + 1, ck },
        { ci, cj, ck - 1 }, { ci, cj, ck + 1 } };
      for (const auto& q : nb)
      {
        if (q[0] < 0 || q[1] < 0 || q[2] < 0 || q[0] >= n[0] || q[1] >= n[1] || q[2] >= n[2])
          continue;
        uint8_t& s = state[cellIndex(q[0], q[1], q[2])];
        if (s == kCellUnknown)
        {
          s = value;
          queue.push_back(cellIndex(q[0], q[1], q[2]));
        }
      }
    }
  }
}

SurfaceDomain::SurfaceDomain(const TriangleSurface& surface, int materialId, const std::string& name)
  : impl_(std::make_unique<Impl>())
  , materialId_(materialId)
{
  setName(name);
  checkMaterialId(materialId, name);
  surface.validateClosed(name);

  std::vector<Point> points;
  points.reserve(surface.points.size());
  for (const auto& p : surface.points)
    points.push_back(toCgal(p));
  std::vector<std::vector<std::size_t>> polygons;
  polygons.reserve(surface.triangles.size());
  for (const auto& t : surface.triangles)
    polygons.push_back({ static_cast<std::size_t>(t[0]), static_cast<std::size_t>(t[1]), static_cast<std::size_t>(t[2]) });
  // Ray parity ignores orientation, but a halfedge mesh needs a consistent one; non-manifold
  // vertices get duplicated here, which the parity test does not mind.
  PMP::orient_polygon_soup(points, polygons);
  if (!PMP::is_polygon_soup_a_polygon_mesh(polygons))
    throw InputError(name + ": surface cannot be oriented consistently (is it self-intersecting or non-orientable?)");
  PMP::polygon_soup_to_polygon_mesh(points, polygons, impl_->mesh);

  for (const auto& p : surface.points)
    impl_->box.add(p);
  impl_->tree = std::make_unique<Tree>(faces(impl_->mesh).first, faces(impl_->mesh).second, impl_->mesh);
  impl_->tree->accelerate_distance_queries();
  impl_->side = std::make_unique<SideOf>(*impl_->tree);
  impl_->buildGrid(surface.triangles.size());
}

SurfaceDomain::~SurfaceDomain() = default;

int SurfaceDomain::material(const Vec3& p) const
{
  const Impl& m = *impl_;
  if (!m.box.contains(p)) // also rejects NaN
    return kOutside;
  const int i = std::min(static_cast<int>((p.x - m.origin.x) * m.invCell.x), m.n[0] - 1);
  const int j = std::min(static_cast<int>((p.y - m.origin.y) * m.invCell.y), m.n[1] - 1);
  const int k = std::min(static_cast<int>((p.z - m.origin.z) * m.invCell.z), m.n[2] - 1);
  const uint8_t s = m.state[m.cellIndex(i, j, k)];
  if (s == kCellBoundary)
    return m.exact(p) ? materialId_ : kOutside;
  return s == kCellInside ? materialId_ : kOutside;
}

bool SurfaceDomain::containsExact(const Vec3& p) const
{
  return impl_->box.contains(p) && impl_->exact(p);
}

void SurfaceDomain::crossings(const Vec3& a, const Vec3& b, std::vector<double>& ts) const
{
  const Vec3 d = b - a;
  const double len2 = dot(d, d);
  if (!(len2 > 0.0))
    return;
  using Hit = Tree::Intersection_and_primitive_id<K::Segment_3>::Type;
  std::vector<Hit> hits;
  impl_->tree->all_intersections(K::Segment_3(toCgal(a), toCgal(b)), std::back_inserter(hits));
  auto param = [&](const Point& p) {
    const double t = dot(Vec3{ p.x() - a.x, p.y() - a.y, p.z() - a.z }, d) / len2;
    ts.push_back(std::clamp(t, 0.0, 1.0));
  };
  for (const auto& hit : hits)
  {
    if (const Point* p = boost::get<Point>(&hit.first))
      param(*p);
    else if (const K::Segment_3* s = boost::get<K::Segment_3>(&hit.first))
    {
      param(s->source());
      param(s->target());
    }
  }
}

BoundingBox SurfaceDomain::bounds() const
{
  return impl_->box;
}

double SurfaceDomain::volume() const
{
  Mesh copy = impl_->mesh;
  PMP::orient_to_bound_a_volume(copy);
  return PMP::volume(copy);
}

size_t SurfaceDomain::numberOfTriangles() const
{
  return impl_->mesh.number_of_faces();
}
}
