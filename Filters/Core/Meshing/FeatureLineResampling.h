// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include "BoundingBox.h"
#include "FeatureNetworkSimplification.h"
#include "FeatureSegments.h"
#include "HierarchicalOracle.h"
#include "OracleMesher.h"

#include <optional>
#include <string>
#include <vector>

namespace omesh
{
/// Feature lines given as many segments far shorter than the mesh size (a noisy surface's sharp
/// edges at a small feature angle) and not resampled: every point stays a mesh vertex and the mesh
/// grades down to them, which costs orders of magnitude more than resampled lines (figures in
/// docs/journal/2026-12-02-slips.md). A warning
/// naming the numbers and the fix, or nothing.
std::optional<std::string> denseFeatureLinesWarning(
  const FeatureSegments& given, const MesherOptions& options, const BoundingBox& inner);

/// The feature lines simplified and resampled as MesherOptions::resampleFeatureLines asks
/// (simplifyFeatureNetwork: chords up to the edge size, else the facet size, else 1/40 of the
/// diagonal, within half the smallest facet distance), or nothing when it does not. Says in
/// `warnings` what changed; `report` gets the simplification's figures.
std::optional<FeatureSegments> resampledFeatures(const FeatureSegments& given, const MesherOptions& options,
  const HierarchicalOracle& oracle, const BoundingBox& inner, std::vector<std::string>& warnings,
  FeatureNetworkReport& report);
}
