// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include "OrientedTriangles.h"
#include "TriangleSurface.h"

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

namespace omesh
{
/// What keeps a triangle surface from bounding a volume by itself: the defects the automatic
/// inside test looks for before it chooses between ray parity and the winding number.
struct SurfaceDefects
{
  std::vector<BorderLoop> holes;                     ///< border loops, longest first
  size_t borderEdges = 0;                            ///< edges used by one triangle
  size_t nonManifoldEdges = 0;                       ///< edges used by more than two triangles
  std::vector<std::pair<int, int>> intersectingPairs; ///< triangles that cross (at most the limit)
  bool moreIntersections = false;                    ///< the limit was reached
  bool orientable = true;                            ///< false: no consistent orientation exists

  /// No defect: the surface is closed, manifold along its edges, orientable and free of
  /// self-intersections, so ray parity decides inside exactly.
  bool none() const
  {
    return holes.empty() && nonManifoldEdges == 0 && intersectingPairs.empty() && orientable;
  }

  /// "2 hole(s) (border loops): ...; 3 non-manifold edge(s); 12 pair(s) of intersecting
  /// triangles, first: triangle 4 (...) and triangle 90 (...)". Empty when none().
  std::string describe(const TriangleSurface& surface) const;
};

/// Finds the defects of `surface` (valid indices: TriangleSurface::validateTriangles; `oriented` =
/// orientTriangles(surface)), listing at most `pairLimit` intersecting pairs.
SurfaceDefects findSurfaceDefects(
  const TriangleSurface& surface, const OrientedTriangles& oriented, size_t pairLimit = 1000);
}
