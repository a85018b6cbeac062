// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include "Domain.h"
#include "TriangleSurface.h"

#include <memory>
#include <string>
#include <vector>

namespace omesh
{
/// How a surface domain decides what is inside.
enum class InsideTest
{
  /// The surface must be closed (every edge shared by two triangles); ray parity (exact).
  Closed,
  /// Generalized winding number above 1/2 (fTetWild's test): surfaces with holes and borders are
  /// accepted, the holes closed smoothly; only points in the surface's bounding box can be inside.
  WindingNumber,
  /// Closed where the surface has no defect (closed, manifold edges, orientable, no
  /// self-intersections: the exact test), else WindingNumber with a warning naming the defects.
  Automatic
};

struct SurfaceOptions
{
  /// With Closed or WindingNumber: accept a surface that intersects itself (the inside test then
  /// decides where it overlaps). Automatic accepts it anyway (with the winding number).
  bool allowSelfIntersections = false;
  InsideTest insideTest = InsideTest::Automatic;
  /// Automatic: what an earlier step (the VTK door's vtkSurfaceDomain) welded of the surface's
  /// seams (SeamWelding::describe), reported among the warnings as a weld here would be.
  std::string weldedBefore;
};

/// The region bounded by a closed triangle surface, one material. Inside tests are exact (CGAL's
/// Side_of_triangle_mesh: ray parity with exact predicates, re-shooting rays that hit an edge or a
/// vertex) behind a precomputed grid that answers points away from the surface in O(1). Segment
/// crossings are exact segment/triangle intersections found through an AABB tree. With
/// InsideTest::WindingNumber the inside test is the generalized winding number (WindingNumber)
/// and crossings also include where it passes 1/2 across a hole (sampled and bisected).
class SurfaceDomain : public Domain
{
public:
  /// Validates (TriangleSurface::validateClosed, or validateTriangles for the winding number and
  /// the automatic test), refuses self-intersections (unless allowed or automatic) and surfaces
  /// that enclose no volume (a lone open patch, a plane), and builds the search structures; throws
  /// InputError naming `name`.
  SurfaceDomain(const TriangleSurface& surface, int materialId, const std::string& name = "Surface",
    const SurfaceOptions& options = {});
  ~SurfaceDomain() override;

  /// What the user should know but that does not stop meshing: the defects the winding number
  /// repairs (holes with their lengths and centres, non-manifold edges, intersecting triangles).
  const std::vector<std::string>& warnings() const { return warnings_; }
  const SurfaceOptions& options() const { return options_; }
  /// Whether inside is decided by the winding number (asked for, or chosen by Automatic).
  bool usesWindingNumber() const;
  /// Distance from p to the nearest input triangle (AABB tree).
  double distanceToSurface(const Vec3& p) const;
  /// The input surface's points (as oriented: non-manifold vertices appear once per fan).
  std::vector<Vec3> surfacePoints() const;

  int material(const Vec3& p) const override;
  void crossings(const Vec3& a, const Vec3& b, std::vector<double>& ts) const override;
  BoundingBox bounds() const override;
  const char* kind() const override { return "Surface"; }
  std::vector<int> materials() const override { return { materialId_ }; }
  /// The sharp edges (CGAL's detect_sharp_edges: the normals of the two triangles differ by more
  /// than featureAngle, as vtkFeatureEdges) chained into polylines between the vertices where other
  /// than two meet. Border edges and edges of zero-area triangles are none.
  std::vector<Crease> creases(double featureAngle, double sagitta) const override;

  int materialId() const { return materialId_; }
  /// Exact inside test without the grid shortcut (for tests and benchmarks).
  bool containsExact(const Vec3& p) const;
  /// Volume enclosed by the surface (with holes: the volume of the oriented triangles closed by
  /// cones to the centre of their box, an estimate).
  double volume() const;
  size_t numberOfTriangles() const;

private:
  struct Impl; // CGAL lives only in the .cxx
  std::unique_ptr<Impl> impl_;
  int materialId_;
  SurfaceOptions options_;
  std::vector<std::string> warnings_;
};
}
