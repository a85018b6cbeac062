// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include "BoundingBox.h"
#include "Vec3.h"

#include <array>
#include <string>
#include <vector>

namespace omesh
{
/// One closed chain of border edges (edges used by one triangle): a hole in the surface.
struct BorderLoop
{
  size_t edges = 0;   ///< number of border edges in the loop
  double length = 0;  ///< summed edge length
  Vec3 centre;        ///< length-weighted centre of the edges
  bool closed = true; ///< false when the chain ends at a non-manifold vertex instead of closing
};

/// Indexed triangle soup, the core's form of a surface input.
struct TriangleSurface
{
  std::vector<Vec3> points;
  std::vector<std::array<int, 3>> triangles;

  /// Throws InputError naming `who` for what no inside test can work with: no triangles, indices
  /// out of range, NaN/infinite or absurd (beyond 1e15) coordinates, triangles repeating a vertex.
  void validateTriangles(const std::string& who) const;

  /// validateTriangles, and throws InputError when the surface cannot bound a volume: edges not
  /// shared by exactly two triangles (the message lists the first offending edges with their
  /// points, and the holes: number of border loops, their lengths and centres).
  void validateClosed(const std::string& who) const;

  /// The edges used by exactly one triangle, as (lower index, higher index), sorted. Needs valid
  /// indices (validateTriangles).
  std::vector<std::array<int, 2>> borderEdges() const;

  /// The border edges (used by exactly one triangle) chained into loops, longest first. Needs
  /// valid indices (validateTriangles).
  std::vector<BorderLoop> borderLoops() const;

  /// "2 hole(s) (border loops): 4 edges, length 0.3 around (1, 2, 3); ..." (the first five).
  static std::string describeHoles(const std::vector<BorderLoop>& loops);

  /// The box around the points.
  BoundingBox bounds() const;

  /// Signed volume (divergence theorem); positive for outward-oriented closed surfaces.
  double signedVolume() const;
};
}
