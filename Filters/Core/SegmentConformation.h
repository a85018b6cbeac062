// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include "FeatureSegments.h"

#include <array>
#include <string>
#include <vector>

namespace omesh
{
/// The constrained segments as they are being refined (paper section 2.1: E_i after the i-th
/// split): points (the input points first) and the sub-segments between them.
struct SegmentSet
{
  std::vector<Vec3> points;
  std::vector<char> corner;             ///< input points (dimension 0 in the mesh)
  std::vector<std::array<int, 3>> subs; ///< end a, end b, input segment
  size_t trims = 0, splits = 0;

  int add(const Vec3& p);
  double length(size_t s) const { return norm(points[subs[s][1]] - points[subs[s][0]]); }
  /// Splits sub-segment s at parameter t from its first end: s becomes (a, m), the new
  /// sub-segment (returned as subs.size() - 1) is (m, b). Returns m.
  int split(size_t s, double t);
};

/// Rule T1 applied to the segments alone (the paper's initial conformation, before any other
/// point): trims the segments at star vertices to l_min/3 (T1.1), then splits at midpoints every
/// sub-segment encroached by a segment point or longer than `edgeSize` (T1.2). Stops with a
/// warning at `maxPoints` points.
SegmentSet conformSegments(
  const FeatureSegments& f, double edgeSize, size_t maxPoints, std::vector<std::string>& warnings);
}
