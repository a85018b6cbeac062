// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include "TriangleSurface.h"

#include <memory>

namespace omesh
{
/// Distances to a triangle soup (open or closed), through CGAL's AABB tree.
class TriangleDistance
{
public:
  explicit TriangleDistance(const TriangleSurface& surface);
  ~TriangleDistance();
  double distance(const Vec3& p) const;

  /// Symmetric Hausdorff distance between two soups, estimated on their vertices, edge midpoints
  /// and triangle centroids.
  static double hausdorff(const TriangleSurface& a, const TriangleSurface& b);

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};
}
