// SPDX-License-Identifier: GPL-3.0-or-later
// The per-feature level of the mesh criteria: the edge size each constrained segment gets.
#pragma once

#include "FeatureSegments.h"
#include "MeshCriteria.h"

#include <optional>
#include <vector>

namespace omesh
{
class HierarchicalOracle;

/// The merge rule of the edge size, from least to most specific: global < per material < per
/// feature. A segment's own value (FeatureSegments::edgeSizes) wins; else the finest of the
/// edge sizes that `materials` (the materials the segment separates or lies in; kOutside ignored)
/// have set at their own level (a domain's criteria or the per-material table, already merged in
/// criteria.perMaterial): the smallest positive one, or 0 (no bound) when each of them says 0;
/// else the global value. 0 means no bound.
double featureEdgeSize(std::optional<double> own, const std::vector<int>& materials, const MaterialCriteria& criteria);

/// True when some material sets its own edge size (then the materials around each segment count).
bool hasMaterialEdgeSizes(const MaterialCriteria& criteria);

/// The materials a segment ab separates or lies in: the oracle's answers at its points at 1/4,
/// 1/2 and 3/4 and on a ring of 16 points around each, 1e-3 |ab| away, perpendicular to ab (a
/// sharp edge of a surface domain gets that domain's material and the material beside it).
/// Sorted, without kOutside.
std::vector<int> materialsAroundSegment(const HierarchicalOracle& oracle, const Vec3& a, const Vec3& b);

/// Every segment's edge size by featureEdgeSize (the oracle is asked only when some material sets
/// its own edge size). Without own values and material edge sizes: the global one everywhere.
std::vector<double> resolveFeatureEdgeSizes(
  const FeatureSegments& features, const MaterialCriteria& criteria, const HierarchicalOracle& oracle);
}
