// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include "TriangleSurface.h"

namespace omesh
{
/// A surface's triangles oriented consistently within each connected piece, as a halfedge mesh
/// needs them.
struct OrientedTriangles
{
  /// The input's points (non-manifold vertices duplicated, appended after them) and its triangles
  /// in their order (triangle i stays triangle i), some reversed.
  TriangleSurface surface;
  /// False when no consistent orientation exists (a self-intersecting or non-orientable input):
  /// the triangles then make no halfedge mesh.
  bool halfedgeMesh = false;
};

/// CGAL's orient_polygon_soup on `surface`: the one place a surface input becomes a polygon soup
/// (the self-intersection test and SurfaceDomain's inside tests both start from it).
OrientedTriangles orientTriangles(const TriangleSurface& surface);
}
