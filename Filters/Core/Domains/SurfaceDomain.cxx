// SPDX-License-Identifier: GPL-3.0-or-later
// The only core translation unit that queries CGAL's AABB tree and Side_of_triangle_mesh (the
// winding number's grid is in SurfaceDomainWinding.cxx).
#include "SurfaceDomainImpl.h"

#include "InputError.h"
#include "OrientedTriangles.h"
#include "SeamWelding.h"
#include "SelfIntersections.h"
#include "SurfaceDefects.h"
#include "WindingOrientation.h"

#include <CGAL/Polygon_mesh_processing/detect_features.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <boost/property_map/function_property_map.hpp>

#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <deque>
#include <numeric>
#include <optional>

namespace omesh
{
namespace
{
namespace PMP = CGAL::Polygon_mesh_processing;

/// The automatic inside test's input: `surface` validated, its unwelded seams welded (an
/// exporter's soup, copies of points not merged), which a warning reports (as it does what an
/// earlier step welded).
const TriangleSurface& weldForAutomatic(const TriangleSurface& surface, const std::string& name,
  const std::string& weldedBefore, std::optional<SeamWelding>& weld, std::vector<std::string>& warnings)
{
  surface.validateTriangles(name);
  if (!weldedBefore.empty())
    warnings.push_back(seamWeldWarning(name, weldedBefore));
  weld = weldSeams(surface, kSeamWeldLimit * norm(surface.bounds().size()));
  if (!weld->welded())
    return surface;
  warnings.push_back(seamWeldWarning(name, weld->describe()));
  return weld->surface;
}
}

std::optional<bool> SurfaceDomain::Impl::crossesOddly(const Point& from, const Point& to, size_t c, bool toIsReference) const
{
  bool odd = false;
  for (uint32_t t = cellFirst[c]; t < cellFirst[c + 1]; ++t)
  {
    const auto& [a, b, d] = triangles[cellTriangles[t]];
    const CGAL::Orientation of = CGAL::orientation(a, b, d, from);
    const CGAL::Orientation ot = toIsReference
      ? static_cast<CGAL::Orientation>(referenceOrientation[t].load(std::memory_order_relaxed))
      : CGAL::orientation(a, b, d, to);
    const std::optional<int> crossed = crossing(a, b, d, from, to, of, ot);
    if (!crossed)
      return std::nullopt;
    odd ^= *crossed != 0;
  }
  return odd;
}

uint8_t SurfaceDomain::Impl::findReferenceSide(int i, int j, int k) const
{
  const size_t c = cellIndex(i, j, k);
  const Point r = toCgal(referencePoint(i, j, k));
  for (uint32_t t = cellFirst[c]; t < cellFirst[c + 1]; ++t)
  {
    const auto& [a, b, d] = triangles[cellTriangles[t]];
    const CGAL::Orientation o = CGAL::orientation(a, b, d, r);
    if (o == CGAL::COPLANAR)
      return kReferenceUnusable; // every query's segment would end on that plane
    referenceOrientation[t].store(static_cast<int8_t>(o), std::memory_order_relaxed);
  }
  // From a face neighbour that no triangle touches, whose side is known: the segment between the
  // two reference points stays in the two cells, so only this cell's triangles can cross it.
  const int nb[6][3] = { { i - 1, j, k }, { i + 1, j, k }, { i, j - 1, k }, { i, j + 1, k }, { i, j, k - 1 }, { i, j, k + 1 } };
  for (const auto& q : nb)
  {
    if (q[0] < 0 || q[1] < 0 || q[2] < 0 || q[0] >= n[0] || q[1] >= n[1] || q[2] >= n[2])
      continue;
    const uint8_t s = state[cellIndex(q[0], q[1], q[2])];
    if (s != kCellInside && s != kCellOutside)
      continue;
    if (const std::optional<bool> odd = crossesOddly(toCgal(referencePoint(q[0], q[1], q[2])), r, c, true))
      return (s == kCellInside) != *odd ? kReferenceInside : kReferenceOutside;
  }
  const CGAL::Bounded_side onSide = (*side)(r);
  if (onSide == CGAL::ON_BOUNDARY)
    return kReferenceUnusable;
  return onSide == CGAL::ON_BOUNDED_SIDE ? kReferenceInside : kReferenceOutside;
}

std::optional<bool> SurfaceDomain::Impl::localSide(const Vec3& p, int i, int j, int k) const
{
  // the segment to the reference point must stay in the (enlarged) cell whose triangles are listed
  const Vec3 lo{ origin.x + i * cell.x, origin.y + j * cell.y, origin.z + k * cell.z };
  for (int a = 0; a < 3; ++a)
    if (!(p[a] >= lo[a] - 0.5 * cellEps && p[a] <= lo[a] + cell[a] + 0.5 * cellEps))
      return std::nullopt;
  const size_t c = cellIndex(i, j, k);
  std::atomic<uint8_t>& known = referenceSide[c];
  uint8_t reference = known.load(std::memory_order_acquire);
  if (reference == kReferenceUnknown)
  {
    reference = findReferenceSide(i, j, k);
    known.store(reference, std::memory_order_release); // threads that race store the same answers
  }
  if (reference == kReferenceUnusable)
    return std::nullopt;
  const std::optional<bool> odd = crossesOddly(toCgal(p), toCgal(referencePoint(i, j, k)), c, true);
  if (!odd)
    return std::nullopt;
  return (reference == kReferenceInside) != *odd;
}

void SurfaceDomain::Impl::buildGrid(size_t numTriangles)
{
  sizeGrid(numTriangles);
  markBoundaryCells();
  classifyFreeCells();
}

void SurfaceDomain::Impl::sizeGrid(size_t numTriangles)
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
}

/// Cells that a triangle touches are boundary cells (answered by localSide, else the exact test);
/// each lists the triangles that touch it.
void SurfaceDomain::Impl::markBoundaryCells()
{
  const double eps = 1e-9 * norm(box.size()); // cells are tested slightly enlarged: rounding cannot hide a touch
  cellEps = eps;
  std::vector<std::pair<uint32_t, uint32_t>> touches; // (cell, triangle)
  for (auto f : mesh.faces())
  {
    auto h0 = mesh.halfedge(f);
    const Point& p0 = mesh.point(mesh.target(h0));
    const Point& p1 = mesh.point(mesh.target(mesh.next(h0)));
    const Point& p2 = mesh.point(mesh.source(h0));
    const K::Triangle_3 tri(p0, p1, p2);
    const bool solid = !CGAL::collinear(p0, p1, p2);
    if (solid)
      triangles.push_back({ p0, p1, p2 });
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
          if (s == kCellBoundary && !solid)
            continue;
          const CGAL::Bbox_3 cb(origin.x + i * cell.x - eps, origin.y + j * cell.y - eps,
            origin.z + k * cell.z - eps, origin.x + (i + 1) * cell.x + eps,
            origin.y + (j + 1) * cell.y + eps, origin.z + (k + 1) * cell.z + eps);
          if (CGAL::do_intersect(tri, cb))
          {
            s = kCellBoundary;
            if (solid)
              touches.emplace_back(static_cast<uint32_t>(cellIndex(i, j, k)), static_cast<uint32_t>(triangles.size() - 1));
          }
        }
  }
  cellFirst.assign(state.size() + 1, 0);
  for (const auto& [c, t] : touches)
    ++cellFirst[c + 1];
  std::partial_sum(cellFirst.begin(), cellFirst.end(), cellFirst.begin());
  cellTriangles.resize(touches.size());
  std::vector<uint32_t> next(cellFirst.begin(), cellFirst.end() - 1);
  for (const auto& [c, t] : touches)
    cellTriangles[next[c]++] = t;
  referenceSide = std::make_unique<std::atomic<uint8_t>[]>(state.size());
  for (size_t c = 0; c < state.size(); ++c)
    referenceSide[c].store(kReferenceUnknown, std::memory_order_relaxed);
  referenceOrientation = std::make_unique<std::atomic<int8_t>[]>(cellTriangles.size());
}

/// Face-adjacent cells that no triangle touches lie on the same side: flood-fill each component
/// and classify it with one exact query at a cell centre.
void SurfaceDomain::Impl::classifyFreeCells()
{
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
      forEachFaceNeighbour(c, [&](size_t d, const int*) {
        uint8_t& s = state[d];
        if (s == kCellUnknown)
        {
          s = value;
          queue.push_back(d);
        }
      });
    }
  }
}

SurfaceDomain::SurfaceDomain(
  const TriangleSurface& surface, int materialId, const std::string& name, const SurfaceOptions& options)
  : impl_(std::make_unique<Impl>())
  , materialId_(materialId)
  , options_(options)
{
  setName(name);
  checkMaterialId(materialId, name);
  bool winding = options.insideTest == InsideTest::WindingNumber;
  std::optional<OrientedTriangles> oriented; // one orientation for the defects and the structures
  std::optional<SeamWelding> weld;
  const TriangleSurface& input = options.insideTest == InsideTest::Automatic
    ? weldForAutomatic(surface, name, options.weldedBefore, weld, warnings_)
    : surface;
  if (options.insideTest == InsideTest::Automatic)
  {
    oriented = orientTriangles(input);
    const SurfaceDefects defects = findSurfaceDefects(input, *oriented);
    winding = !defects.none();
    if (winding)
      warnings_.push_back(name + ": surface does not bound a volume by itself: " + defects.describe(input) +
        "; inside is where the generalized winding number exceeds 1/2 (holes closed smoothly, overlaps inside)");
  }
  else if (winding)
  {
    surface.validateTriangles(name);
    const std::vector<BorderLoop> loops = surface.borderLoops();
    if (!loops.empty())
      warnings_.push_back(name + ": surface is not closed: " + TriangleSurface::describeHoles(loops) +
        "; the winding-number inside test closes them");
  }
  else
    surface.validateClosed(name);
  if (options.insideTest != InsideTest::Automatic && !options.allowSelfIntersections)
    refuseSelfIntersections(surface, name);

  // Ray parity ignores orientation, but a halfedge mesh needs a consistent one; non-manifold
  // vertices get duplicated here, which the parity test does not mind.
  if (!oriented)
    oriented = orientTriangles(input);
  if (!oriented->halfedgeMesh)
    throw InputError(name + ": surface cannot be oriented consistently (is it self-intersecting or non-orientable?)");
  if (winding)
    orientComponentsForWinding(oriented->surface, input);
  PMP::polygon_soup_to_polygon_mesh(oriented->surface.points, oriented->surface.triangles, impl_->mesh,
    CGAL::parameters::point_map(boost::make_function_property_map<Vec3>(&toCgal)));
  // A closed surface that does not intersect itself (checked above) has winding number 1 exactly
  // where ray parity says inside: the fast test with the grid gives the same answers.
  const bool parityAgrees = options.insideTest == InsideTest::WindingNumber && !options.allowSelfIntersections &&
    input.borderLoops().empty();

  impl_->box = input.bounds();
  // Zero-area triangles (collinear or coincident corners, as CAD exports have) hold no interior
  // that a ray could cross, and their edges are their neighbours' edges: leave them out of the
  // tree. Side_of_triangle_mesh shot random rays forever from a point on one (found by fuzzing).
  std::vector<Mesh::Face_index> solid;
  solid.reserve(impl_->mesh.number_of_faces());
  for (auto f : impl_->mesh.faces())
  {
    auto h = impl_->mesh.halfedge(f);
    if (!CGAL::collinear(impl_->mesh.point(impl_->mesh.source(h)), impl_->mesh.point(impl_->mesh.target(h)),
          impl_->mesh.point(impl_->mesh.target(impl_->mesh.next(h)))))
      solid.push_back(f);
  }
  if (solid.empty())
    throw InputError(name + ": every triangle of the surface has zero area");
  impl_->tree = std::make_unique<Tree>(solid.begin(), solid.end(), impl_->mesh);
  // Built now rather than lazily by the first query, under CGAL's lock, when the parallel
  // refinement queries from several threads (Domain: const queries are thread-safe).
  impl_->tree->build();
  impl_->tree->accelerate_distance_queries();
  if (winding && !parityAgrees)
  {
    impl_->winding = std::make_unique<WindingNumber>(oriented->surface.points, oriented->surface.triangles);
    refuseIfNoVolume(*impl_->winding, oriented->surface, name);
    impl_->buildWindingGrid(input.triangles.size());
    return;
  }
  impl_->side = std::make_unique<SideOf>(*impl_->tree);
  impl_->buildGrid(input.triangles.size());
}

bool SurfaceDomain::usesWindingNumber() const
{
  return impl_->winding != nullptr;
}

double SurfaceDomain::distanceToSurface(const Vec3& p) const
{
  return std::sqrt(impl_->tree->squared_distance(toCgal(p)));
}

std::vector<Vec3> SurfaceDomain::surfacePoints() const
{
  std::vector<Vec3> out;
  out.reserve(impl_->mesh.number_of_vertices());
  for (auto v : impl_->mesh.vertices())
  {
    const Point& p = impl_->mesh.point(v);
    out.push_back({ p.x(), p.y(), p.z() });
  }
  return out;
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
  if (m.winding)
    return m.windingInside(p) ? materialId_ : kOutside;
  const uint8_t s = m.state[m.cellIndex(i, j, k)];
  if (s == kCellBoundary)
  {
    const std::optional<bool> local = m.localSide(p, i, j, k);
    return (local ? *local : m.exact(p)) ? materialId_ : kOutside;
  }
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
  if (!(len2 > 0.0) || !isFinite(d)) // also NaN ends (outside every domain) and ends 1e308 apart
    return;
  // parameters by projection; for segments longer than 1e154 (len2 overflows) along the longest axis
  const int axis = std::abs(d.x) >= std::abs(d.y) && std::abs(d.x) >= std::abs(d.z) ? 0 : (std::abs(d.y) >= std::abs(d.z) ? 1 : 2);
  const bool project = std::isfinite(len2);
  const size_t firstHit = ts.size();
  using Hit = Tree::Intersection_and_primitive_id<K::Segment_3>::Type;
  std::vector<Hit> hits;
  impl_->tree->all_intersections(K::Segment_3(toCgal(a), toCgal(b)), std::back_inserter(hits));
  auto param = [&](const Point& p) {
    const Vec3 q{ p.x() - a.x, p.y() - a.y, p.z() - a.z };
    const double t = project ? dot(q, d) / len2 : q[axis] / d[axis];
    if (std::isfinite(t))
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
  if (impl_->winding && impl_->winding->hasBorder())
    impl_->windingCrossings(a, b, ts, firstHit);
}

BoundingBox SurfaceDomain::bounds() const
{
  return impl_->box;
}

double SurfaceDomain::volume() const
{
  if (impl_->winding)
  {
    const Vec3 c = 0.5 * (impl_->box.min + impl_->box.max);
    double v = 0.0;
    for (auto f : impl_->mesh.faces())
    {
      auto h = impl_->mesh.halfedge(f);
      Vec3 q[3];
      for (int k = 0; k < 3; ++k, h = impl_->mesh.next(h))
      {
        const Point& p = impl_->mesh.point(impl_->mesh.source(h));
        q[k] = Vec3{ p.x(), p.y(), p.z() } - c;
      }
      v += dot(q[0], cross(q[1], q[2]));
    }
    return v / 6.0;
  }
  Mesh copy = impl_->mesh;
  PMP::orient_to_bound_a_volume(copy);
  return PMP::volume(copy);
}

std::vector<Crease> SurfaceDomain::creases(double featureAngle, double) const
{
  const Mesh& mesh = impl_->mesh;
  using Edge = Mesh::Edge_index;
  using Vertex = Mesh::Vertex_index;
  std::vector<char> sharp(mesh.number_of_edges(), 0);
  PMP::detect_sharp_edges(mesh, featureAngle,
    boost::make_function_property_map<Edge, char&>([&](Edge e) -> char& { return sharp[e.idx()]; }));
  auto toVec = [&](Vertex v) {
    const Point& p = mesh.point(v);
    return Vec3{ p.x(), p.y(), p.z() };
  };
  auto faceNormal = [&](Mesh::Halfedge_index h, Vec3& n) {
    const Vec3 a = toVec(mesh.source(h)), b = toVec(mesh.target(h)), c = toVec(mesh.target(mesh.next(h)));
    const Vec3 m = cross(b - a, c - a);
    if (!(norm(m) > 0))
      return false;
    n = (1.0 / norm(m)) * m;
    return true;
  };
  // the sharp edges as a graph on the vertices; an edge beside a zero-area triangle has no normal
  std::vector<std::vector<Mesh::Halfedge_index>> out(mesh.number_of_vertices());
  std::vector<std::array<Vec3, 2>> normals(mesh.number_of_edges());
  for (Edge e : mesh.edges())
  {
    if (!sharp[e.idx()] || mesh.is_border(e))
      continue;
    const auto h = mesh.halfedge(e);
    auto& n = normals[e.idx()];
    if (!faceNormal(h, n[0]) || !faceNormal(mesh.opposite(h), n[1]))
      continue;
    out[mesh.source(h).idx()].push_back(h);
    out[mesh.target(h).idx()].push_back(mesh.opposite(h));
  }
  std::vector<bool> walked(mesh.number_of_edges(), false);
  std::vector<Crease> creases;
  auto walk = [&](Mesh::Halfedge_index h) {
    Crease c;
    c.dihedral = 180.0;
    c.points.push_back(toVec(mesh.source(h)));
    for (;;)
    {
      const Edge e = mesh.edge(h);
      walked[e.idx()] = true;
      c.points.push_back(toVec(mesh.target(h)));
      c.normals.push_back(normals[e.idx()]);
      const double cosine = std::clamp(dot(normals[e.idx()][0], normals[e.idx()][1]), -1.0, 1.0);
      c.dihedral = std::min(c.dihedral, 180.0 - std::acos(cosine) * 180.0 / M_PI);
      const auto& next = out[mesh.target(h).idx()];
      if (next.size() != 2)
        break;
      h = walked[mesh.edge(next[0]).idx()] ? next[1] : next[0];
      if (walked[mesh.edge(h).idx()])
        break; // back at the start of a loop
    }
    creases.push_back(std::move(c));
  };
  for (Vertex v : mesh.vertices()) // chains from their ends, then the loops
    if (out[v.idx()].size() != 2)
      for (auto h : out[v.idx()])
        if (!walked[mesh.edge(h).idx()])
          walk(h);
  for (Vertex v : mesh.vertices())
    for (auto h : out[v.idx()])
      if (!walked[mesh.edge(h).idx()])
        walk(h);
  return creases;
}

size_t SurfaceDomain::numberOfTriangles() const
{
  return impl_->mesh.number_of_faces();
}
}
