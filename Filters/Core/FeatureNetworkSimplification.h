// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include "FeatureSegments.h"

#include <cstddef>

namespace omesh
{
/// How far simplifyFeatureNetwork may go, from the mesh's edge size h.
struct FeatureNetworkTolerances
{
  double edgeLength = 0.0;     ///< h: chords up to this (resampleFeatureLines' maxLength)
  double chordTolerance = 0.0; ///< resampleFeatureLines' tolerance (dropped points to their chord)
  /// Points closer than mergeFraction * h become one; a point closer than that to a segment becomes
  /// a point of it. 1/3 (the paper's T1.1 fraction) bounds the angles left between segments of at
  /// most h from below by asin(1/3) = 19.5 degrees.
  double mergeFraction = 1.0 / 3.0;
  /// Two segments meeting at less than this (degrees) share a trunk: the longer is replaced by the
  /// shorter and the chord from its far end (lines then move by at most half the shorter segment
  /// at 30 degrees). The segment level handles wider angles by midpoint splits alone
  /// (SegmentSet::kClusterAngle).
  double minAngle = 30.0;
  /// Dangling chains from a branch point shorter than spurFraction * h, and separate pieces
  /// (chains, loops) shorter than that, are dropped: whiskers the mesh cannot show anyway.
  double spurFraction = 1.0;
  double mergeDistance() const { return mergeFraction * edgeLength; }
  double spurLength() const { return spurFraction * edgeLength; }
};

/// What simplifyFeatureNetwork did and how far the lines moved.
struct FeatureNetworkReport
{
  std::size_t pointsMerged = 0;    ///< points merged into a nearby kept point
  std::size_t pointsSnapped = 0;   ///< segments split at a point closer than the merge distance
  std::size_t spursDropped = 0;    ///< dangling chains shorter than the spur length
  std::size_t piecesDropped = 0;   ///< separate chains and loops shorter than the spur length
  std::size_t pointsResampled = 0; ///< points resampleFeatureLines dropped
  /// Hausdorff distances (sampled at h / 50) between the given and the simplified lines, both ways.
  double givenToSimplified = 0.0;
  double simplifiedToGiven = 0.0;
  double smallestAngle = 180.0;   ///< degrees, between simplified segments sharing a point
  double shortestSegment = 0.0;
};

/// Feature lines found as sharp edges of noisy surfaces form networks in which nearly every point
/// is a branch point with small angles between its segments, so chain resampling alone keeps them
/// almost as they are. This simplifies the network first, keeping only input points (they lie on
/// the input surfaces):
///  1. points closer than the merge distance d are merged, greedily, into the branch point of
///     highest degree among them (then the lowest index): every point moves by at most d, and the
///     kept points are at least d apart;
///  2. a point closer than d to a segment it does not end becomes a point of that segment (lines
///     meeting at a small angle then share a trunk instead of running side by side);
///  3. dangling chains from a branch point shorter than the spur length, and separate chains and
///     loops shorter than it, are dropped (a branch point left with only such chains keeps its
///     longest);
///  4. chains between the remaining branch points and corners are resampled (resampleFeatureLines);
///  5. step 2 again on the chords.
/// Bounds (d = merge distance, t = chord tolerance, s = spur length, k = snap rounds, at most 8):
/// every simplified segment lies within d + k d + t of the given lines; every given point lies within
/// d + k d + t of the simplified lines, or on a dropped spur or piece (within s + d of a kept point, or
/// in a piece shorter than s). Both distances are measured and reported.
FeatureNetworkReport simplifyFeatureNetwork(FeatureSegments& f, const FeatureNetworkTolerances& tolerances);

/// Largest distance from a point of the lines `from` to the lines `to`, from samples at most
/// `spacing` apart on `from` (so at most spacing / 2 below the true one-sided Hausdorff distance).
/// 0 when `from` is empty; infinity when only `to` is.
double featureLinesDistance(const FeatureSegments& from, const FeatureSegments& to, double spacing);
}
