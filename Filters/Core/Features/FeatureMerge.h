// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include "FeatureSegments.h"

#include <cstddef>

namespace omesh
{
/// What mergeFeatureSegments changed.
struct FeatureMergeCounts
{
  std::size_t mergedPoints = 0;   ///< points with the coordinates of an earlier point, made one
  std::size_t duplicates = 0;     ///< segments listed again (either direction), dropped
  std::size_t overlapping = 0;    ///< segments that overlapped a collinear one (before the merge)
  std::size_t overlapGroups = 0;  ///< groups of overlapping segments, each replaced by its union
  bool changed() const { return mergedPoints || duplicates || overlapping; }
};

/// Cleans feature lines the way users produce them (the outputs of several vtkFeatureEdges
/// appended, a polyline drawn twice): points with identical coordinates become one vertex, repeated
/// segments are dropped, and collinear segments that overlap (exact predicates) are replaced by
/// the pieces of their union between consecutive end points. Own edge sizes (edgeSizes) go with
/// their segments; one piece given two different ones is an InputError naming it. Sources
/// (FeatureSegments::source) go with them too: a repeated segment's is the first listed, a piece
/// of a union the first covering segment's. Segments that cross or touch without
/// overlapping are left as they are (FeatureSegments::validate refuses them), so are zero-length
/// ones. Points that no segment uses any more are removed. Does nothing when a coordinate is not
/// finite (validate names it).
FeatureMergeCounts mergeFeatureSegments(FeatureSegments& features);
}
