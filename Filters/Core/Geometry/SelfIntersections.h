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
/// Pairs of triangles (input indices, smaller first, sorted) of `surface` that intersect other
/// than along the edges and vertices they share: CGAL's Polygon_mesh_processing::self_intersections
/// with exact predicates. Triangles that only touch at a vertex that both use (two solids welded at
/// a corner) are not reported. Stops after `limit` pairs. Needs valid indices (validateTriangles).
std::vector<std::pair<int, int>> selfIntersections(const TriangleSurface& surface, size_t limit = 1000);
/// The same with `oriented = orientTriangles(surface)` already at hand.
std::vector<std::pair<int, int>> selfIntersections(
  const TriangleSurface& surface, const OrientedTriangles& oriented, size_t limit = 1000);

/// "triangle 4 ((0, 0, 0), (1, 0, 0), (0, 1, 0))": a triangle of `surface` by its id and corners.
std::string describeTriangle(const TriangleSurface& surface, int t);

/// Throws InputError naming `who` when the surface intersects itself: the number of intersecting
/// pairs and the first pair's triangle ids and corner coordinates.
void refuseSelfIntersections(const TriangleSurface& surface, const std::string& who);
}
