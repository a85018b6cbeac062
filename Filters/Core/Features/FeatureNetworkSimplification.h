// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include "FeatureSegments.h"

#include <cstddef>
#include <functional>
#include <limits>

namespace omesh
{
/// How far simplifyFeatureNetwork may go, from the mesh's edge size h.
struct FeatureNetworkTolerances
{
  double edgeLength = 0.0;     ///< h: chords up to this (resampleFeatureLines' maxLength)
  double chordTolerance = 0.0; ///< resampleFeatureLines' tolerance (dropped points to their chord)
  /// Points closer than mergeFraction * h become one; a point closer than that to a segment becomes
  /// a point of it. At 1 (the default) the lines keep no detail finer than the mesh can show: points
  /// at least h apart, so the segment level starts from pieces of h / 3 (T1.1) and seldom reaches
  /// its split floor; at 1/3 the noisy spheres' poles (input triangles far below h, crumpled by the noise)
  /// still lost pieces below that floor (Benchmarks/noisy_features.py).
  double mergeFraction = 1.0;
  /// Two segments meeting at less than this (degrees) share a trunk: the longer is replaced by the
  /// shorter and the chord from its far end (lines then move by at most half the shorter segment
  /// at 30 degrees). The segment level handles wider angles by midpoint splits alone
  /// (SegmentSet::kClusterAngle).
  double minAngle = 30.0;
  /// Dangling chains from a branch point shorter than spurFraction * h, and separate pieces
  /// (chains, loops) shorter than that, are dropped: whiskers the mesh cannot show anyway.
  double spurFraction = 1.0;
  /// Where the mesh will be (the oracle's materials, with a margin of a thousandth of the segment's
  /// length, as the mesher's own test): simplified segments that leave it are dropped, they could not
  /// become mesh edges. Empty: everywhere.
  std::function<bool(const Vec3&)> inDomain;
  /// How far steps 1, 2 and 5 may move the lines from the given ones: a merge (step 1) or a snap
  /// or shared trunk (steps 2, 5) is made only where every segment it makes stays within this of
  /// the given lines (sampled at a quarter of it), so that no line moves farther than the chords
  /// of step 4 may. Infinity (the default): unbounded, the merge distance alone decides (noisy
  /// networks, whose points are all within noise of each other). The mesher's resampling sets it
  /// to the chord tolerance: a polygonal circle smaller than the edge size keeps its shape (its
  /// points, closer than h, were merged into a few: a 16-gon of radius 1 at h = 1 lost 11.7 % of
  /// its volume, Benchmarks/cad_defects item 6), as do corners and sharp turns.
  double maxDeviation = std::numeric_limits<double>::infinity();
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
  std::size_t segmentsOutside = 0; ///< simplified segments that left the domain, dropped
  /// points where a segment could not end as a mesh edge (a thin spike or fold of the domain in
  /// the plane of its segments), bypassed or their segments dropped
  std::size_t unmeshableEnds = 0;
  /// Hausdorff distances (sampled at h / 50) between the given and the simplified lines, both ways;
  /// from the given lines without their separate pieces shorter than the spur length.
  double givenToSimplified = 0.0;
  double simplifiedToGiven = 0.0;
  double shortPiecesLength = 0.0; ///< total length of the given lines' separate pieces shorter than the spur length
  double smallestAngle = 180.0;   ///< degrees, between simplified segments sharing a point
  double shortestSegment = 0.0;
};

/// Feature lines found as sharp edges of noisy surfaces form networks in which nearly every point
/// is a branch point with small angles between its segments, so chain resampling alone keeps them
/// almost as they are. This simplifies the network first, keeping only input points (they lie on
/// the input surfaces):
///  1. points closer than the merge distance d are merged, greedily, into the point of highest
///     degree among them (then the lowest index; a kd-tree range search): every point moves by at
///     most d, and the kept points are at least d apart;
///  2. a point closer than d to a segment it does not end becomes a point of that segment (a
///     near-touch becomes a junction), and two segments meeting at less than minAngle share a trunk
///     (the longer becomes the shorter plus the chord from its far end): the lines' total length
///     drops with each such step, so it ends; rounds of independent steps, at most 64;
///  3. dangling chains from a branch point shorter than the spur length s, and separate chains and
///     loops shorter than s, are dropped (a branch point left with only such chains keeps its
///     longest);
///  4. chains between the remaining branch points and corners are resampled (resampleFeatureLines);
///  5. step 2 again on the chords;
///  6. with inDomain, segments that leave the domain are dropped, and points where the domain
///     has no room for cells around their segments (a thin spike or fold in the segments' plane:
///     no mesh could hold those segments as edges there) are bypassed by their neighbours' chord
///     or lose those segments (then step 3 again).
/// What it guarantees: kept points are input points at least d apart (so no segment is shorter
/// than d; with a finite maxDeviation only where merging them kept the lines that near the given
/// ones, and no merge, snap or trunk moves them farther); at the end of step 2 no two segments sharing a point meet at less than minAngle (the
/// measured smallest angle is reported, as resampling's chords and step 6 come after). How far the
/// lines move is measured, both ways, and reported rather than bounded a priori: a merge moves a
/// line by at most d, a trunk by at most half its shorter segment, a chord by at most the chord
/// tolerance, but steps 2, 3 and 6 compose (on the noisy spheres: simplified to given 0.5-0.6 h,
/// given to simplified 1.2-2.7 h where chords outside the surface or at spike tips were dropped).
/// Provenance: f.source is set to, per segment, the index of the segment of f as passed that it
/// came from (FeatureSegments::source: a piece of a split or snap keeps its segment's, a merged
/// copy of a segment that stayed in place is that one, a chord or a bypass takes the segment it
/// covers most of), and each segment keeps that one's own edge size (edgeSizes).
FeatureNetworkReport simplifyFeatureNetwork(FeatureSegments& f, const FeatureNetworkTolerances& tolerances);

/// Largest distance from a point of the lines `from` to the lines `to`, from samples at most
/// `spacing` apart on `from` (so at most spacing / 2 below the true one-sided Hausdorff distance).
/// 0 when `from` is empty; infinity when only `to` is.
double featureLinesDistance(const FeatureSegments& from, const FeatureSegments& to, double spacing);
}
