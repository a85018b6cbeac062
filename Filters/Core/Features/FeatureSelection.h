// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include "FeatureSegments.h"
#include "OracleFeatureLines.h"

#include <array>
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

namespace omesh
{
class HierarchicalOracle;
struct MaterialCriteria;

/// Which feature lines the mesher keeps: none, the given ones (user polylines, sharp edges of a
/// surface), the ones found where the inputs meet (findFeatureLines), or both.
enum class FeatureSource
{
  None,
  Given,
  Automatic,
  Both
};

/// The default, the one source of it (the VTK filter, the plugin XML, the scene loader and the
/// command line take theirs from here): Given. Not Both (Automatic when no lines are given): valid
/// everywhere measured and 1.03x the tetrahedra on the demo, but 1.08-1.33x on the generated cases,
/// and every call pays the search (docs/FEATURE-LINES.md).
constexpr FeatureSource kDefaultFeatureSource = FeatureSource::Given;

const char* toString(FeatureSource s);

/// The lines to mesh and what was done to get them.
struct FeatureSelection
{
  FeatureSegments segments;           ///< given (as they are) then automatic, vertices shared where equal
  FeatureLines automatic;             ///< the lines found (all of them, before dropping any)
  std::size_t droppedAutomatic = 0;   ///< automatic segments dropped because they cross a given one
  std::size_t droppedUnmeshable = 0;  ///< automatic segments dropped because no material touches them
  std::size_t droppedAlongGiven = 0;  ///< automatic segments dropped because they run along a given line
  std::size_t droppedNearDuplicate = 0; ///< automatic segments dropped because they run along another curve found
  std::size_t trunksShared = 0;       ///< automatic segments rerouted because they left a vertex at < 30 degrees to another
  std::vector<std::string> warnings;  ///< the search's (small angles), the drops
  /// Per segment of `segments`: found where the inputs meet or given, and the materials an
  /// automatic one separates (ascending, -2 for none; the given ones: all -2).
  struct Origin
  {
    bool automatic = false;
    std::array<int, 4> materials{ -2, -2, -2, -2 };
  };
  std::vector<Origin> origin;
};

/// The lines the mesher gets for `source`. Automatic lines are resampled within a tenth of the
/// smallest facet distance of the materials they separate, to chords of at most their facet size
/// (creases: as long as that tolerance allows; never below the edge size) which the mesher splits to
/// the edge size (T1.2); the search grid is half the edge size (their smallest; else the facet size,
/// else 1/40 of the oracle's diagonal, as MesherOptions::resampleFeatureLines). Given lines win: an automatic segment that crosses a given one is dropped
/// (with a warning), so a rim given by hand and found again does not make the lines invalid. The
/// given lines keep their own edge sizes (FeatureSegments::edgeSizes), also on the pieces of a split.
/// `creaseAngle` and `progress` as FeatureLineOptions' (the creases of single inputs are found above
/// that angle; 180 = none).
FeatureSelection selectFeatures(const HierarchicalOracle& oracle, const FeatureSegments& given, FeatureSource source,
  const MaterialCriteria& criteria, double creaseAngle = kDefaultCreaseAngle,
  const std::function<bool(double)>& progress = {});

/// The search options selectFeatures derives from the criteria (see there).
FeatureLineOptions featureLineOptions(const HierarchicalOracle& oracle, const MaterialCriteria& criteria);
}
