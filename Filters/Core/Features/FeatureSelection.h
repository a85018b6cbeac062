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
/// command line take theirs from here): Given, the meshes of before. Not Both (Automatic when no
/// lines are given), which issue 13 suggests: with resampling the found lines are moved by up to
/// 1.7 mm, and the found lines cost 1.1-2.6x the tetrahedra (README, "Feature lines where inputs meet").
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
  /// The segment of `segments` nearest to x (-1 when there are none): for pieces of lines the
  /// mesher simplified, whose numbering is its own.
  int nearestSegment(const Vec3& x) const;
};

/// The lines the mesher gets for `source`. Automatic lines are resampled to the edge size of the
/// materials they separate (their smallest; else the facet size, else 1/40 of the oracle's diagonal,
/// as MesherOptions::resampleFeatureLines) within a tenth of the smallest facet distance; the search grid
/// is half that fine. Given lines win: an automatic segment that crosses a given one is dropped
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
