// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include "FeatureSegments.h"

#include <cstddef>

namespace omesh
{
/// What mergeFeatureSegments changed.
struct FeatureMergeCounts
{
  std::size_t mergedPoints = 0;   ///< points at the place of an earlier point (same coordinates or within rounding), made one
  std::size_t splitSegments = 0;  ///< segments split at feature points lying on them within rounding
  /// points merged with another, and segments split, that were not exactly at the same place
  /// (within rounding only); firstWithinRounding: the first such point
  std::size_t withinRounding = 0;
  Vec3 firstWithinRounding{ 0, 0, 0 };
  std::size_t duplicates = 0;     ///< segments listed again (either direction), dropped
  std::size_t overlapping = 0;    ///< segments that overlapped a collinear one (before the merge)
  std::size_t overlapGroups = 0;  ///< groups of overlapping segments, each replaced by its union
  std::size_t crossings = 0;      ///< pairs of segments that crossed or touched inside one, split there
  bool changed() const { return mergedPoints || duplicates || overlapping || crossings || splitSegments; }
};

/// Cleans feature lines the way users produce them (the outputs of several vtkFeatureEdges
/// appended, a polyline drawn twice): points with identical coordinates, or closer than rounding
/// (1e-10 of the lines' bounding-box diagonal), become one vertex (the first listed), a segment
/// passing that close to another feature point is split there (two parts' edges that coincide up
/// to rounding become one line), repeated segments are dropped, and collinear segments that
/// overlap (exact predicates) are replaced by the pieces of their union between consecutive end
/// points. Segments that cross (an X) or touch
/// inside one of them (a T: one's end on the other) are split there, at a new shared point for an
/// X, at the end for a T: the sharp edges of parts meeting face to face cross on the shared face.
/// Own edge sizes (edgeSizes) go with
/// their segments; one piece given two different ones is an InputError naming it. Sources
/// (FeatureSegments::source) go with them too: a repeated segment's is the first listed, a piece
/// of a union or of a split segment the first covering segment's. Zero-length segments are left
/// as they are (validate refuses them). Points that no segment uses any more are removed (not
/// after a split alone). Does nothing when a coordinate is not finite (validate names it).
FeatureMergeCounts mergeFeatureSegments(FeatureSegments& features);
}
