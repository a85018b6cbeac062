// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include "TriangleSurface.h"

#include <cstddef>
#include <string>

namespace omesh
{
/// The automatic inside test welds seams at most this fraction of the surface's bounding-box
/// diagonal wide; wider ones stay cracks, which the winding number closes. Far below any facet
/// distance a mesh is made with.
constexpr double kSeamWeldLimit = 1e-3;

/// What weldSeams did.
struct SeamWelding
{
  /// The input with each welded group of points merged into one at their mean (the other points
  /// and every triangle kept, in their order).
  TriangleSurface surface;
  std::vector<int> pointIndex; ///< per input point, its index in `surface`
  size_t borderEdges = 0;  ///< the input's border edges
  size_t pairedEdges = 0;  ///< of them, the sides of welded seams
  size_t mergedPoints = 0; ///< points that are gone (merged into another)
  double widestGap = 0.0;  ///< the largest distance between matching ends of a welded seam
  double largestMove = 0.0;
  bool welded() const { return mergedPoints > 0; }
  /// "welded 1200 unwelded seam edge(s) (of 1300 border edges): 800 point(s) merged, moved by at
  /// most 1e-05 (gaps up to 2e-05)".
  std::string describe() const;
};

/// Welds a surface's unwelded seams: border edges that pair up as the two sides of one seam
/// (pairSeams, either way round, unambiguous, gap at most `limit`) have their matching ends merged.
/// A group of points whose merge would move one farther than `limit` or twice the group's widest
/// gap, or join two corners of a triangle, is left as it is. Needs valid indices (TriangleSurface::validateTriangles).
SeamWelding weldSeams(const TriangleSurface& surface, double limit);

/// The warning that reports a weld: "<name>: <SeamWelding::describe> (a triangle soup, ...)".
std::string seamWeldWarning(const std::string& name, const std::string& description);
}
