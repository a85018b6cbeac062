// SPDX-License-Identifier: GPL-3.0-or-later
// SurfaceDomain's private parts, shared by its two translation units (SurfaceDomain.cxx: the
// parity grid and the public calls; SurfaceDomainWinding.cxx: the winding number's grid and
// crossings). Not for other code: CGAL lives here.
#pragma once

#include "SurfaceDomain.h"
#include "WindingNumber.h"

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Surface_mesh.h>

#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

namespace omesh
{
namespace surface_detail
{
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = K::Point_3;
using Mesh = CGAL::Surface_mesh<Point>;
using SideOf = CGAL::Side_of_triangle_mesh<Mesh, K>;
using Tree = SideOf::AABB_tree;

inline Point toCgal(const Vec3& p) { return { p.x, p.y, p.z }; }

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
inline std::optional<int> crossing(const Point& a, const Point& b, const Point& c, const Point& from, const Point& to,
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

/// Where in its cell the reference point lies (fractions of the cell): off the centre, so that the
/// faces of an axis-aligned part seldom hold it.
inline constexpr double kReferenceOffset[3] = { 0.4637, 0.5183, 0.4821 };
}
using namespace surface_detail;

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
}
