// SPDX-License-Identifier: GPL-3.0-or-later
// The only core translation unit that instantiates CGAL's AABB tree and Side_of_triangle_mesh.
#include "SurfaceDomain.h"

#include "InputError.h"
#include "OrientedTriangles.h"
#include "SeamWelding.h"
#include "SelfIntersections.h"
#include "SurfaceDefects.h"
#include "WindingNumber.h"
#include "WindingOrientation.h"

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/detect_features.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Surface_mesh.h>
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

/// The side of a boundary cell's reference point, found at the cell's first query.
enum ReferenceSide : uint8_t
{
  kReferenceUnknown = 0,
  kReferenceOutside = 1,
  kReferenceInside = 2,
  kReferenceUnusable = 3 // on the surface or on a triangle's plane: the cell's queries go to the exact test
};

/// How segment from-to crosses triangle abc, its ends on sides `of` and `ot` of the triangle's
/// plane: +1 from the front (where (b - a) x (c - a) points) to the back, -1 the other way, 0 not at
/// all; nothing where an end lies on the plane (on the triangle, its edge, or beside it) or the
/// segment passes through an edge or a vertex.
std::optional<int> crossing(const Point& a, const Point& b, const Point& c, const Point& from, const Point& to,
  CGAL::Orientation of, CGAL::Orientation ot)
{
  if (of == CGAL::COPLANAR || ot == CGAL::COPLANAR)
    return std::nullopt;
  if (of == ot)
    return 0;
  const CGAL::Orientation e0 = CGAL::orientation(from, to, a, b);
  const CGAL::Orientation e1 = CGAL::orientation(from, to, b, c);
  const CGAL::Orientation e2 = CGAL::orientation(from, to, c, a);
  if (e0 == CGAL::COPLANAR || e1 == CGAL::COPLANAR || e2 == CGAL::COPLANAR)
    return std::nullopt;
  if (e0 != e1 || e1 != e2)
    return 0;
  return of == CGAL::POSITIVE ? 1 : -1;
}

/// Unwelded seams farther apart than this fraction of the diagonal are not welded (they stay
/// cracks, which the winding number closes): far below any facet distance a mesh is made with.
constexpr double kSeamWeldLimit = 1e-3;

/// The automatic inside test's input: `surface` validated, its unwelded seams welded (an
/// exporter's soup, copies of points not merged), which a warning reports.
const TriangleSurface& weldForAutomatic(
  const TriangleSurface& surface, const std::string& name, std::optional<SeamWelding>& weld, std::vector<std::string>& warnings)
{
  surface.validateTriangles(name);
  weld = weldSeams(surface, kSeamWeldLimit * norm(surface.bounds().size()));
  if (!weld->welded())
    return surface;
  warnings.push_back(name + ": " + weld->describe() + " (a triangle soup, or copies of points not merged?); " +
    "the mesh follows the welded surface");
  return weld->surface;
}

/// Where in its cell the reference point lies (fractions of the cell): off the centre, so that the
/// faces of an axis-aligned part seldom hold it.
constexpr double kReferenceOffset[3] = { 0.4637, 0.5183, 0.4821 };
}

struct SurfaceDomain::Impl
{
  Mesh mesh;
  std::unique_ptr<Tree> tree;
  std::unique_ptr<SideOf> side;
  std::unique_ptr<WindingNumber> winding; // InsideTest::WindingNumber: instead of side and grid
  BoundingBox box;
  // Inside/outside/boundary classification of a uniform grid over the box: a query in a cell that
  // no triangle touches takes that cell's answer, every other query goes to the exact test.
  int n[3] = { 1, 1, 1 };
  Vec3 origin, invCell, cell;
  std::vector<uint8_t> state;
  // Per boundary cell, the triangles that touch it (compressed rows over all cells; zero-area ones
  // left out as in the tree) and the side of its reference point: a query in the cell counts the
  // crossings of the segment to that point with these triangles only, since the segment stays in
  // the cell. Exact predicates; any degenerate crossing goes to the exact test.
  std::vector<uint32_t> cellFirst, cellTriangles;
  std::vector<std::array<Point, 3>> triangles;
  std::unique_ptr<std::atomic<uint8_t>[]> referenceSide;
  // per entry of cellTriangles: the side of the triangle's plane the cell's reference point lies on
  // (written before referenceSide, which is stored with release)
  std::unique_ptr<std::atomic<int8_t>[]> referenceOrientation;
  double cellEps = 0.0; // the cells' enlargement when their triangles were listed
  // The winding number on the same grid: w at every cell's reference point within a known error,
  // and a bound of |grad w| over the cell. Off the surface |grad w| is bounded by the border alone
  // (WindingNumber::gradientBound; 0 for closed pieces), and w changes by +-1 where a segment
  // crosses a triangle. So w(p) = w(reference) + the signed crossings of the segment between them
  // (+1 entering a triangle from its front), within the reference's error plus the bound times the
  // segment's length; found for all cells at once by a breadth-first walk over face neighbours
  // (buildWindingGrid), evaluated exactly where the error would grow too large or a crossing is
  // degenerate.
  std::vector<double> windingAtReference;
  std::vector<float> windingError, windingSlope;
  /// Signed crossings of segment from-to with the triangles of cells c (and d, unless it is c);
  /// nothing when an end lies on a triangle's plane or the segment passes through an edge.
  std::optional<int> signedCrossings(const Point& from, const Point& to, size_t c, size_t d) const;

  /// The winding number that defines inside (WindingNumber::approximate: the exact sum is some ten
  /// times dearer on large surfaces); every answer of the domain is taken from it.
  double windingAt(const Vec3& p) const { return winding->approximate(p); }
  /// The error of windingAt against the true winding number, which the gradient bound is about.
  static constexpr double kApproximation = WindingNumber::kApproximationError;
  bool exact(const Vec3& p) const
  {
    if (winding)
      return windingAt(p) > 0.5;
    return (*side)(toCgal(p)) != CGAL::ON_UNBOUNDED_SIDE;
  }
  /// Where the winding number passes 1/2 between the triangle hits of segment ab (across holes).
  void windingCrossings(const Vec3& a, const Vec3& b, std::vector<double>& ts, size_t firstHit) const;
  /// w at parameter t of a segment, within `error`.
  struct Sample
  {
    double t = 0.0, w = 0.0, error = 0.0;
  };
  /// The passes of w through 1/2 on the piece [lo.t, hi.t] of ab, where no triangle crosses it:
  /// none where the gradient bound rules them out, else halves (twice at most) and bisects a
  /// change of side.
  void passes(const Vec3& a, const Vec3& b, double length, Sample lo, Sample hi, int depth, std::vector<double>& ts) const;
  size_t cellIndex(int i, int j, int k) const
  {
    return static_cast<size_t>(i) + static_cast<size_t>(n[0]) * (static_cast<size_t>(j) + static_cast<size_t>(n[1]) * k);
  }
  Vec3 referencePoint(size_t c) const
  {
    return referencePoint(static_cast<int>(c % n[0]), static_cast<int>((c / n[0]) % n[1]),
      static_cast<int>(c / (static_cast<size_t>(n[0]) * n[1])));
  }
  Vec3 referencePoint(int i, int j, int k) const
  {
    return { origin.x + (i + kReferenceOffset[0]) * cell.x, origin.y + (j + kReferenceOffset[1]) * cell.y,
      origin.z + (k + kReferenceOffset[2]) * cell.z };
  }
  /// The inside test in boundary cell (i, j, k) by local parity; nothing where it cannot decide.
  std::optional<bool> localSide(const Vec3& p, int i, int j, int k) const;
  /// Whether segment from-to crosses cell c's triangles an odd number of times; nothing where an
  /// end lies on a triangle's plane or the segment passes through an edge or a vertex.
  /// (toIsReference: `to` is the cell's reference point, whose orientations are known.)
  std::optional<bool> crossesOddly(const Point& from, const Point& to, size_t c, bool toIsReference = false) const;
  /// The side of the cell's reference point (kReferenceUnusable where no query could use it).
  uint8_t findReferenceSide(int i, int j, int k) const;
  /// The winding number at p, evaluated (within `error` = kApproximation of the true one).
  double evaluate(const Vec3& p, double& error) const
  {
    error = kApproximation;
    return windingAt(p);
  }
  /// Whether windingAt(p) lies on the side of 1/2 that `w`, an estimate of the true winding number
  /// within `error`, shows.
  static bool decides(double w, double error) { return std::abs(w - 0.5) > error + kApproximation; }
  /// The winding number at p from its cell's data, within `error` (kApproximation where it evaluated it).
  double windingEstimate(const Vec3& p, double& error) const;
  /// w(p) > 1/2: from the estimate where its error allows, else evaluated.
  bool windingInside(const Vec3& p) const;
  /// windingSlope of every cell.
  void boundWindingSlopes();
  /// Carries w from cell c's reference point to neighbour d's (buildWindingGrid); false where the
  /// error would grow too large or a crossing is degenerate.
  bool carryWinding(size_t c, size_t d);
  BoundingBox cellBox(int i, int j, int k, double grow) const
  {
    BoundingBox b;
    b.add(Vec3{ origin.x + i * cell.x - grow, origin.y + j * cell.y - grow, origin.z + k * cell.z - grow });
    b.add(Vec3{ origin.x + (i + 1) * cell.x + grow, origin.y + (j + 1) * cell.y + grow, origin.z + (k + 1) * cell.z + grow });
    return b;
  }
  /// Calls f(d, q) for each face neighbour d (grid coordinates q) of cell c inside the grid.
  template <class F>
  void forEachFaceNeighbour(size_t c, F&& f) const
  {
    const int i = static_cast<int>(c % n[0]);
    const int j = static_cast<int>((c / n[0]) % n[1]);
    const int k = static_cast<int>(c / (static_cast<size_t>(n[0]) * n[1]));
    const int nb[6][3] = { { i - 1, j, k }, { i + 1, j, k }, { i, j - 1, k }, { i, j + 1, k }, { i, j, k - 1 }, { i, j, k + 1 } };
    for (const auto& q : nb)
      if (q[0] >= 0 && q[1] >= 0 && q[2] >= 0 && q[0] < n[0] && q[1] < n[1] && q[2] < n[2])
        f(cellIndex(q[0], q[1], q[2]), q);
  }
  void buildWindingGrid(size_t numTriangles);
  void buildGrid(size_t numTriangles);
  void sizeGrid(size_t numTriangles);
  void markBoundaryCells();
  void classifyFreeCells();
};

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

std::optional<int> SurfaceDomain::Impl::signedCrossings(const Point& from, const Point& to, size_t c, size_t d) const
{
  int count = 0;
  for (int pass = 0; pass < (d == c ? 1 : 2); ++pass)
  {
    const size_t cellOf = pass == 0 ? c : d;
    for (uint32_t t = cellFirst[cellOf]; t < cellFirst[cellOf + 1]; ++t)
    {
      const uint32_t id = cellTriangles[t];
      if (pass == 1 && std::find(cellTriangles.begin() + cellFirst[c], cellTriangles.begin() + cellFirst[c + 1], id) !=
            cellTriangles.begin() + cellFirst[c + 1])
        continue; // listed in both cells: counted once
      const auto& [a, b, e] = triangles[id];
      const std::optional<int> crossed =
        crossing(a, b, e, from, to, CGAL::orientation(a, b, e, from), CGAL::orientation(a, b, e, to));
      if (!crossed)
        return std::nullopt;
      count += *crossed;
    }
  }
  return count;
}

double SurfaceDomain::Impl::windingEstimate(const Vec3& p, double& error) const
{
  const int i = std::clamp(static_cast<int>((p.x - origin.x) * invCell.x), 0, n[0] - 1);
  const int j = std::clamp(static_cast<int>((p.y - origin.y) * invCell.y), 0, n[1] - 1);
  const int k = std::clamp(static_cast<int>((p.z - origin.z) * invCell.z), 0, n[2] - 1);
  // the segment to the reference point must stay in the (enlarged) cell whose triangles are listed
  const Vec3 lo{ origin.x + i * cell.x, origin.y + j * cell.y, origin.z + k * cell.z };
  for (int a = 0; a < 3; ++a)
    if (!(p[a] >= lo[a] - 0.5 * cellEps && p[a] <= lo[a] + cell[a] + 0.5 * cellEps))
    {
      return evaluate(p, error);
    }
  const size_t c = cellIndex(i, j, k);
  const Vec3 r = referencePoint(i, j, k);
  double w = windingAtReference[c];
  if (state[c] == kCellBoundary)
  {
    const std::optional<int> crossed = signedCrossings(toCgal(r), toCgal(p), c, c);
    if (!crossed)
      return evaluate(p, error);
    w += *crossed;
  }
  error = windingError[c] + windingSlope[c] * norm(p - r);
  return w;
}

bool SurfaceDomain::Impl::windingInside(const Vec3& p) const
{
  double error = 0.0;
  const double w = windingEstimate(p, error);
  if (decides(w, error))
    return w > 0.5;
  return windingAt(p) > 0.5;
}

void SurfaceDomain::Impl::buildWindingGrid(size_t numTriangles)
{
  sizeGrid(numTriangles);
  markBoundaryCells();
  const size_t cells = state.size();
  windingAtReference.assign(cells, 0.0);
  windingError.assign(cells, std::numeric_limits<float>::infinity());
  windingSlope.assign(cells, 0.0f);
  if (winding->hasBorder())
    boundWindingSlopes();
  // Walk from cell 0, carrying w across faces (from any neighbour that has a value, where the first
  // cannot); an evaluation restarts the error where it would pass kMaxError and come within
  // kMaxError of 1/2 (near holes), or at a degenerate crossing. A cell whose bound is infinite (the
  // border passes through it) cannot use its reference point: no evaluation there.
  std::vector<char> seen(cells, 0);
  std::deque<size_t> queue{ 0 };
  seen[0] = 1;
  auto evaluateReference = [&](size_t c) {
    double error = 0.0;
    if (std::isfinite(windingSlope[c]))
    {
      windingAtReference[c] = evaluate(referencePoint(c), error);
      windingError[c] = static_cast<float>(error);
    }
  };
  evaluateReference(0);
  while (!queue.empty())
  {
    const size_t c = queue.front();
    queue.pop_front();
    forEachFaceNeighbour(c, [&](size_t d, const int*) {
      if (seen[d])
        return;
      seen[d] = 1;
      queue.push_back(d);
      if (carryWinding(c, d))
        return;
      bool carried = false;
      forEachFaceNeighbour(d, [&](size_t e, const int*) { carried = carried || (e != c && seen[e] && carryWinding(e, d)); });
      if (!carried)
        evaluateReference(d);
    });
  }
}

bool SurfaceDomain::Impl::carryWinding(size_t c, size_t d)
{
  constexpr float kMaxError = 0.2f;
  const Vec3 from = referencePoint(c), to = referencePoint(d);
  const float error = windingError[c] + std::max(windingSlope[c], windingSlope[d]) * static_cast<float>(norm(to - from));
  if (!std::isfinite(error))
    return false;
  const std::optional<int> crossed = signedCrossings(toCgal(from), toCgal(to), c, d);
  // the error may grow while it cannot take w across 1/2 (far from holes w stays near 0 or 1)
  if (!crossed || error > std::max(kMaxError, static_cast<float>(std::abs(windingAtReference[c] + *crossed - 0.5)) - kMaxError))
    return false;
  windingAtReference[d] = windingAtReference[c] + *crossed;
  windingError[d] = error;
  return true;
}

void SurfaceDomain::Impl::boundWindingSlopes()
{
  // a bound over a block of 4^3 cells holds in each of them: one call per block, and per cell only
  // in blocks where it is infinite (the border passes through them)
  constexpr int kBlock = 4;
  for (int k0 = 0; k0 < n[2]; k0 += kBlock)
    for (int j0 = 0; j0 < n[1]; j0 += kBlock)
      for (int i0 = 0; i0 < n[0]; i0 += kBlock)
      {
        const int i1 = std::min(i0 + kBlock, n[0]) - 1, j1 = std::min(j0 + kBlock, n[1]) - 1, k1 = std::min(k0 + kBlock, n[2]) - 1;
        BoundingBox block = cellBox(i0, j0, k0, cellEps);
        block.add(cellBox(i1, j1, k1, cellEps));
        const double blockBound = winding->gradientBound(block);
        for (int k = k0; k <= k1; ++k)
          for (int j = j0; j <= j1; ++j)
            for (int i = i0; i <= i1; ++i)
              windingSlope[cellIndex(i, j, k)] = static_cast<float>(
                std::isfinite(blockBound) ? blockBound : winding->gradientBound(cellBox(i, j, k, cellEps)));
      }
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

void SurfaceDomain::Impl::windingCrossings(const Vec3& a, const Vec3& b, std::vector<double>& ts, size_t firstHit) const
{
  // clip ab to the box: outside it nothing is inside
  const Vec3 d = b - a;
  double t0 = 0.0, t1 = 1.0;
  if (!box.clip(a, d, t0, t1))
    return;
  ts.push_back(t0);
  ts.push_back(t1);
  // between two triangle hits the winding number is continuous: look for where it passes 1/2
  std::vector<double> ends{ t0, t1 };
  for (size_t i = firstHit; i < ts.size(); ++i)
    if (ts[i] > t0 && ts[i] < t1)
      ends.push_back(ts[i]);
  std::sort(ends.begin(), ends.end());
  const double length = norm(d);
  for (size_t e = 0; e + 1 < ends.size(); ++e)
  {
    const double lo = ends[e], hi = ends[e + 1];
    if (!(hi > lo))
      continue;
    Sample from{ lo + 1e-3 * (hi - lo) }, to{ hi - 1e-3 * (hi - lo) };
    from.w = windingEstimate(lerp(a, b, from.t), from.error);
    to.w = windingEstimate(lerp(a, b, to.t), to.error);
    passes(a, b, length, from, to, 0, ts);
  }
}

void SurfaceDomain::Impl::passes(const Vec3& a, const Vec3& b, double length, Sample lo, Sample hi, int depth,
  std::vector<double>& ts) const
{
  constexpr int kMaxDepth = 2; // 4 pieces where the bound cannot rule a pass out
  // w changes by at most L |dt| along the piece: no pass when both ends lie certainly on one side
  // and |w - 1/2| at the ends adds up to more than that
  auto certain = [](const Sample& s) { return std::abs(s.w - 0.5) - s.error - kApproximation; };
  auto sharpen = [&](Sample& s) {
    if (s.error > kApproximation)
      s.w = evaluate(lerp(a, b, s.t), s.error);
  };
  for (int round = 0; round < 2; ++round)
  {
    if (certain(lo) > 0 && certain(hi) > 0 && (lo.w > 0.5) == (hi.w > 0.5))
    {
      BoundingBox piece;
      piece.add(lerp(a, b, lo.t));
      piece.add(lerp(a, b, hi.t));
      if (certain(lo) + certain(hi) > winding->gradientBound(piece) * (hi.t - lo.t) * length)
        return;
    }
    if (lo.error <= kApproximation && hi.error <= kApproximation)
      break;
    sharpen(lo); // the grid's estimates could not decide: evaluations
    sharpen(hi);
  }
  if (depth < kMaxDepth)
  {
    Sample mid{ 0.5 * (lo.t + hi.t) };
    mid.w = evaluate(lerp(a, b, mid.t), mid.error);
    passes(a, b, length, lo, mid, depth + 1, ts);
    passes(a, b, length, mid, hi, depth + 1, ts);
    return;
  }
  auto side = [&](const Sample& s) {
    return decides(s.w, s.error) ? s.w > 0.5 : windingAt(lerp(a, b, s.t)) > 0.5;
  };
  const bool insideLo = side(lo);
  if (insideLo == side(hi))
    return;
  double x = lo.t, y = hi.t;
  while (y - x > 1e-12 * (1.0 + std::abs(y)))
  {
    const double mid = 0.5 * (x + y);
    ((windingAt(lerp(a, b, mid)) > 0.5) == insideLo ? x : y) = mid;
  }
  ts.push_back(y);
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
  const TriangleSurface& input = options.insideTest == InsideTest::Automatic ? weldForAutomatic(surface, name, weld, warnings_) : surface;
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
  // A closed surface that does not intersect itself (checked above) has winding number 1 exactly
  // where ray parity says inside: the fast test with the grid gives the same answers.
  const bool parityAgrees = options.insideTest == InsideTest::WindingNumber && !options.allowSelfIntersections &&
    input.borderLoops().empty();
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
