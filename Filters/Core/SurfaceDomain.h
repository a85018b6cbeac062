// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include "Domain.h"
#include "TriangleSurface.h"

#include <memory>

namespace omesh
{
/// The region bounded by a closed triangle surface, one material. Inside tests are exact (CGAL's
/// Side_of_triangle_mesh: ray parity with exact predicates, re-shooting rays that hit an edge or a
/// vertex) behind a precomputed grid that answers points away from the surface in O(1). Segment
/// crossings are exact segment/triangle intersections found through an AABB tree.
class SurfaceDomain : public Domain
{
public:
  /// Validates (TriangleSurface::validateClosed) and builds the search structures; throws InputError.
  SurfaceDomain(const TriangleSurface& surface, int materialId, const std::string& name = "Surface");
  ~SurfaceDomain() override;

  int material(const Vec3& p) const override;
  void crossings(const Vec3& a, const Vec3& b, std::vector<double>& ts) const override;
  BoundingBox bounds() const override;
  const char* kind() const override { return "Surface"; }
  std::vector<int> materials() const override { return { materialId_ }; }

  int materialId() const { return materialId_; }
  /// Exact inside test without the grid shortcut (for tests and benchmarks).
  bool containsExact(const Vec3& p) const;
  /// Volume enclosed by the surface.
  double volume() const;
  size_t numberOfTriangles() const;

private:
  struct Impl; // CGAL lives only in the .cxx
  std::unique_ptr<Impl> impl_;
  int materialId_;
};
}
