// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include "Vec3.h"

#include <array>
#include <string>
#include <vector>

namespace omesh
{
/// Indexed triangle soup, the core's form of a surface input.
struct TriangleSurface
{
  std::vector<Vec3> points;
  std::vector<std::array<int, 3>> triangles;

  /// Throws InputError naming `who` when the surface cannot bound a volume: no triangles, indices
  /// out of range, NaN/infinite coordinates, triangles repeating a vertex, or edges not shared by
  /// exactly two triangles (the message lists the first offending edges with their points).
  void validateClosed(const std::string& who) const;

  /// Signed volume (divergence theorem); positive for outward-oriented closed surfaces.
  double signedVolume() const;
};
}
