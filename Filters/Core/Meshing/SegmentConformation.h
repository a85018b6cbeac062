// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include "FeatureSegments.h"

#include <array>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace omesh
{
/// The constrained segments as they are being refined (paper section 2.1: E_i after the i-th
/// split): points (the input points first) and the sub-segments between them.
///
/// Small angles: segments that leave a vertex at a small angle encroach each other's pieces
/// without end when each is split at its own midpoints (a point of one lands inside a diametral
/// ball of the other, whose split lands inside one of the first, ...). Such segments form a
/// cluster at that vertex (the apex), and every split near the apex is mirrored on the other
/// segments of its cluster at the same distance from the apex (concentric shells, as in
/// Shewchuk's and Cheng-Dey-Ramos' work): points at equal distances from the apex never lie in
/// each other's diametral balls, so a cluster splits only as far as the rest of the mesh asks.
struct SegmentSet
{
  std::vector<Vec3> points;
  std::vector<char> corner;             ///< input points (dimension 0 in the mesh)
  std::vector<std::array<int, 3>> subs; ///< end a, end b, input segment
  size_t trims = 0, splits = 0, mirrored = 0;

  /// Starts from the input segments, one sub-segment each, and finds the small-angle clusters.
  explicit SegmentSet(const FeatureSegments& f);
  SegmentSet() = default;

  int add(const Vec3& p);
  double length(size_t s) const { return norm(points[subs[s][1]] - points[subs[s][0]]); }
  /// Splits sub-segment s at parameter t from its first end: s becomes (a, m), the new
  /// sub-segment (returned as subs.size() - 1) is (m, b). Returns m.
  int split(size_t s, double t);

  /// The splits (sub-segment, parameter) that keep the shells of s's cluster when s is split at
  /// t: the point at the same distance from the apex on each other segment of the cluster, where
  /// that distance lies within the nearer half of that segment and is no point yet. Empty when s
  /// lies on no cluster. Distances are compared after scaling (scale_). A mirrored point closer
  /// than a quarter of s's length to a point of the other segment is left out: it would make a
  /// piece much shorter than the one being split.
  std::vector<std::pair<int, double>> mirrorSplits(size_t s, double t) const;

  /// Distance from the apex at which segment `input`'s point `at` (an end point of the input)
  /// trims it: `cut`, scaled as the shells of its cluster are (see mirrorSplits).
  double shellDistance(int input, int at, double cut) const;

  /// Segments meeting at less than this angle (degrees) at a shared vertex form a cluster there.
  /// Wider angles split well at midpoints; mirroring there only adds points (a corner
  /// tetrahedron's 45 and 60 degree corners lost pieces to short mirrored ones).
  static constexpr double kClusterAngle = 30.0;

private:
  std::vector<std::array<int, 2>> inputEnds_;             ///< the input segment's end points
  std::vector<std::array<std::vector<int>, 2>> cluster_;  ///< per input segment and end: the others of its cluster there
  /// Per input segment and end: its shells' scale, 1 + 1e-9 x its rank in the cluster. Shells at
  /// exactly equal distances on coplanar segments make cocircular points, hence flat Delaunay
  /// tetrahedra; a relative 1e-9 breaks the tie for the exact predicates and stays far inside
  /// the no-encroachment margin (about angle^2 / 2: 1.5e-6 at 0.1 degrees).
  std::vector<std::array<double, 2>> scale_;
  std::vector<std::vector<int>> subsOfInput_;             ///< sub-segments of each input segment
};

/// Rule T1 applied to the segments alone (the paper's initial conformation, before any other
/// point): trims the segments at star vertices to l_min/3 (T1.1), then splits at midpoints every
/// sub-segment encroached by a segment point or longer than its input segment's edge size
/// `edgeSizes[input]` (T1.2; one per input segment, resolveFeatureEdgeSizes; <= 0 = no bound),
/// mirrored in small-angle clusters. Stops with a warning at `maxPoints` points. Calls `check`
/// (which may throw: the mesher's deadline) at every sub-segment it looks at.
SegmentSet conformSegments(const FeatureSegments& f, const std::vector<double>& edgeSizes, size_t maxPoints,
  std::vector<std::string>& warnings, const std::function<void()>& check = {});
/// The same with one edge size for every segment.
SegmentSet conformSegments(const FeatureSegments& f, double edgeSize, size_t maxPoints,
  std::vector<std::string>& warnings, const std::function<void()>& check = {});
}
