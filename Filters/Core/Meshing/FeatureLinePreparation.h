// SPDX-License-Identifier: GPL-3.0-or-later
// The feature lines one meshing run gets: the given lines simplified on their own, then combined
// with the ones found where the inputs meet.
#pragma once

#include "FeatureNetworkSimplification.h"
#include "FeatureSegments.h"
#include "FeatureSelection.h"
#include "MeshCriteria.h"

#include <cstddef>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace omesh
{
class HierarchicalOracle;
struct MesherOptions;

/// The given lines simplified and resampled as MesherOptions::resampleFeatureLines asks
/// (simplifyFeatureNetwork: chords up to the edge size, else the facet size, else 1/40 of the
/// diagonal, within half the smallest facet distance), with each chord keeping the edge size of the
/// given line nearest to it; nothing when `given` is empty. A warning when the lines changed.
std::optional<FeatureSegments> simplifyGivenFeatureLines(const FeatureSegments& given, const MaterialCriteria& criteria,
  const HierarchicalOracle& oracle, FeatureNetworkReport& report, std::vector<std::string>& warnings);

/// The statistics of a simplification (feature_network.*, feature_segments_before_resampling).
void addFeatureNetworkStatistics(
  const FeatureNetworkReport& report, std::size_t givenSegments, std::map<std::string, double>& statistics);

/// The lines the mesher gets and what was done to the given ones.
struct PreparedFeatureLines
{
  FeatureSelection selection;                  ///< selection.segments go to meshOracle
  std::optional<FeatureNetworkReport> network; ///< of the given lines' simplification, when it ran
  std::size_t givenSegments = 0;               ///< the given lines' segments before it
  std::vector<std::string> warnings;           ///< the simplification's, then the selection's
  /// addFeatureNetworkStatistics when the simplification ran (the mesher's statistics, as when it simplified).
  void addStatistics(std::map<std::string, double>& statistics) const;
};

/// In this order: the given lines simplified on their own (when options.resampleFeatureLines, for
/// Given and Both), then combined with the lines found where the inputs meet (selectFeatures for
/// `source`); `options.resampleFeatureLines` is then turned off, since meshOracle would simplify
/// the combined lines again and move the found ones, which the search resampled to their chord
/// length already with every vertex on the true curve (to 1e-10). `progress` as selectFeatures'.
PreparedFeatureLines prepareFeatureLines(const HierarchicalOracle& oracle, const FeatureSegments& given,
  FeatureSource source, MesherOptions& options, const std::function<bool(double)>& progress = {});
}
