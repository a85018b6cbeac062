// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include "Vec3.h"

#include <array>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace omesh
{
class HierarchicalOracle;

/// The constrained segments E of the paper: points and segments between them (polylines split
/// into segments; a point shared by several polylines is one vertex).
struct FeatureSegments
{
  std::vector<Vec3> points;
  std::vector<std::array<int, 2>> segments;
  /// Each segment's own edge size (the per-feature level of the criteria, MeshCriteria.h): empty
  /// when no line has one, else one entry per segment, unset (nullopt) where the line gives none.
  /// 0 is "no bound" (it overrides the materials' and the global value). A value must be finite
  /// and >= 0 (validate). Functions that rebuild the segments carry it (mergeFeatureSegments,
  /// transferEdgeSizes).
  std::vector<std::optional<double>> edgeSizes;
  /// Each segment's provenance: the index of the segment it came from in the lines a rebuild
  /// started from (simplifyFeatureNetwork: the lines as passed to it; >= 0). Empty when not tracked,
  /// else one per segment. Functions that rebuild the segments carry it (mergeFeatureSegments,
  /// resampleFeatureLines, simplifyFeatureNetwork's steps): a piece of a split keeps its segment's,
  /// a chord takes the one most of the length it replaces came from (sourceOfMost), of copies made
  /// one the first's. Tags and edge sizes follow it: a line moved beside another by the rebuild is
  /// still the same line, which its distances no longer tell.
  std::vector<int> source;

  bool empty() const { return segments.empty(); }
  double length(size_t s) const { return norm(points[segments[s][1]] - points[segments[s][0]]); }

  /// Checks what the paper's algorithm needs. Throws InputError for NaN points, indices out of
  /// range, zero-length segments, segments crossing each other (named by index and
  /// coordinates), points within rounding of another point or segment (not merged: mergeFeatureSegments) and own edge sizes that are negative, NaN or infinite (checkEdgeSizes). Returns warnings for what it cannot guarantee: angles below 60 degrees between
  /// segments at a shared vertex, segments outside every domain of `oracle`, and a radius-edge
  /// bound B < 1 / (2 sin alpha0) that contradicts the smallest angle alpha0.
  std::vector<std::string> validate(const HierarchicalOracle& oracle, double radiusEdgeBound) const;

  /// Pairs (s, t), s < t, of segments that cross, touch other than at a shared end point, or
  /// overlap (exact predicates), sorted. Expects finite points and valid indices.
  std::vector<std::pair<size_t, size_t>> crossingPairs() const;

  /// For each point, the segments that end there.
  std::vector<std::vector<size_t>> incidence() const;

  /// Points that end at least two segments (the paper's star vertices).
  std::vector<bool> starVertices() const;
  /// Per segment and end (segments[s][0], [1]): whether another segment at that end meets it at
  /// less than 90 degrees. Only then can a point of another segment there lie in one of its
  /// diametral balls near that end (across 90 degrees or more every point of the other lies beyond
  /// the plane through the vertex normal to it, which bounds those balls), so only then does T1.1's
  /// trim buy anything (a vertex inside a polyline that samples a smooth curve has none).
  std::vector<std::array<bool, 2>> endsBelowRightAngle() const;

  /// Smallest angle (degrees) between two segments sharing a vertex; 180 if none share one.
  double smallestAngle() const;

  /// The source (see there) of the largest part of the total length of `segs` (the first on a
  /// tie), -1 when source is empty: what a chord replacing those segments came from.
  int sourceOfMost(const std::vector<size_t>& segs) const;

  /// Segment s's own edge size (nullopt when it has none).
  std::optional<double> edgeSize(size_t s) const { return s < edgeSizes.size() ? edgeSizes[s] : std::nullopt; }
  /// Throws InputError naming the segment when an own edge size is negative, NaN or infinite, or
  /// when edgeSizes is neither empty nor one per segment.
  void checkEdgeSizes() const;
  /// "segment 3 (x, y, z) - (x, y, z)", as the errors name a segment.
  std::string describe(size_t s) const;
};

/// Gives each segment of `to` the own edge size of the segment of `from` nearest to its midpoint,
/// when that one has an own value and lies within `maxDistance` of the midpoint (else unset): for
/// given lines split where automatic lines meet them, whose pieces stay on them (selectFeatures;
/// where a rebuild moves lines, the nearest segment can be another line's: simplifyFeatureNetwork
/// goes by FeatureSegments::source). Leaves `to.edgeSizes` empty when `from` has none.
void transferEdgeSizes(const FeatureSegments& from, FeatureSegments& to, double maxDistance);

/// Angle (degrees) at v between the directions to p and to q.
double angleAt(const Vec3& v, const Vec3& p, const Vec3& q);

/// Feature lines that come as many tiny, noisy segments (sharp edges of a scanned or finely
/// triangulated surface) meet at small angles all along and cost the mesher a point per wiggle.
/// Resampling keeps the corners (points where other than two segments meet, or where the line
/// turns by more than `cornerAngle` degrees) and, between them, only the input points needed so
/// that every dropped point lies within `tolerance` of the chord that replaces it and no chord
/// is longer than `maxLength` (unless it was one input segment). Kept points are input points,
/// so the chords stay on the feature line as given. Closed loops without a corner keep their
/// sharpest point; two chains between the same corners that fit one chord become one segment.
/// Own edge sizes are not kept; the source (when tracked) is. Returns the number of points dropped.
size_t resampleFeatureLines(FeatureSegments& f, double maxLength, double tolerance, double cornerAngle = 60.0);
}
