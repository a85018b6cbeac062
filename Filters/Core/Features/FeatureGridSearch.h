// SPDX-License-Identifier: GPL-3.0-or-later
// The first phase of the feature-line search (findFeatureLines): the regions at the points of a
// grid over the oracle; on the faces of the cubes whose corners differ, the crossings of curves,
// located exactly (FeatureCrossings.h); in each cube, crossings with the same regions linked in
// pairs (one curve passing) and the others left to end at a junction of the touching cubes. Links
// are then refined where the curve bends between them. GridCrossings is all later phases read.
#pragma once

#include "FeatureCrossings.h"
#include "FeatureCurveLocator.h"
#include "OracleFeatureLines.h"

#include <cstddef>
#include <cstdint>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

namespace omesh::featurelines
{
/// Two crossings on one curve with nothing found between them.
struct Link
{
  int a, b;
};

/// Where curves meet: the centre of the cubes they end in and the crossings ending there.
struct Junction
{
  Vec3 centre;
  std::vector<int> ending;
};

/// What the grid search found.
struct GridCrossings
{
  double spacing = 0.0;   ///< the grid step
  double diagonal = 0.0;  ///< of the oracle's bounding box
  double precision = 0.0; ///< to which crossings are located
  /// The crossings on grid faces (gridFacesCrossed of them), then those refineLinks inserted.
  std::vector<Crossing> crossings;
  std::size_t gridFacesCrossed = 0;
  std::vector<Link> links;
  std::vector<Junction> junctions;
};

/// Calls options.progress with `fraction`; throws FeatureSearchAborted when it asks to stop.
void reportProgress(const FeatureLineOptions& options, double fraction);

class FeatureGridSearch
{
public:
  /// The grid: two steps of room around the materials, the spacing widened (with a warning appended
  /// to `warnings`) to stay within options.maximumGridPoints. Throws InputError for an empty or
  /// unbounded oracle or a spacing that is not a positive number.
  FeatureGridSearch(const HierarchicalOracle& oracle, const FeatureLineOptions& options, std::vector<std::string>& warnings);

  /// The steps below in order; the grid search's result.
  GridCrossings search();

  /// 1. Regions at the grid points.
  void classifyGridPoints();
  /// 2. Grid faces of mixed cubes: walked along their edges, then bisected where a curve passes;
  /// in each cube, crossings of the same regions in pairs are linked, the others end at a junction.
  void findCrossings();
  /// 3. Between two crossings joined in a cube the curve may bend (a corner of a box, a tight
  /// curve): the crossing on the plane halfway between them, where it lies off their chord, is
  /// inserted, and so on down to the tolerance; corners are then kept within a 256th of a grid step.
  void refineLinks();
  /// 4. Curves that meet near a face or corner of the grid end in neighbouring cubes (one arm in
  /// each): cubes where curves end and that touch (26 neighbours) are one junction, where two or
  /// more end.
  void mergeJunctionCubes();

  const GridCrossings& found() const { return found_; }

private:
  std::int64_t index(std::int64_t i, std::int64_t j, std::int64_t k) const { return i + nx_ * (j + ny_ * k); }
  Vec3 pointAt(std::int64_t id) const
  {
    const std::int64_t i = id % nx_, j = (id / nx_) % ny_, k = id / (nx_ * ny_);
    return Vec3{ origin_.x + i * h_, origin_.y + j * h_, origin_.z + k * h_ };
  }
  const EdgeRegions& edge(std::int64_t p, int axis);
  int face(std::int64_t p, int axis);
  void linkCube(std::int64_t p);
  void pairPasses(const std::vector<int>& ids);
  void refine(const FeatureCurveLocator& locator, int a, int b, int depth, std::vector<int>& path);

  const HierarchicalOracle& oracle_;
  const FeatureLineOptions& options_;
  GridCrossings found_;
  double h_ = 0, tolerance_ = 0;
  Vec3 origin_;
  std::int64_t nx_ = 0, ny_ = 0, nz_ = 0;
  std::int64_t stride_[3] = { 0, 0, 0 };
  std::vector<Region> region_;
  std::unordered_map<std::int64_t, EdgeRegions> edges_;
  std::unordered_map<std::int64_t, int> faceCrossing_; // 3 * lowest corner + normal axis -> crossing or -1
  std::vector<std::pair<std::int64_t, std::vector<int>>> junctionCubes_; // cube, curves ending in it
};
}
