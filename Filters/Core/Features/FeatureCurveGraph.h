// SPDX-License-Identifier: GPL-3.0-or-later
// The second phase of the feature-line search (findFeatureLines): the graph of the crossings the
// grid search found, linked as it linked them, and one junction vertex per junction where curves
// end, placed from their tangents. Its chains, from junction to junction or around a loop, are the
// curves; each carries the regions of its crossings.
#pragma once

#include "FeatureGridSearch.h"

#include <vector>

namespace omesh::featurelines
{
class FeatureCurveGraph
{
public:
  /// Vertices 0..crossingCount()-1 are found.crossings, the rest junctions (found.junctions).
  explicit FeatureCurveGraph(const GridCrossings& found);

  /// Curves: chains between junctions and vertices that do not continue exactly one curve, then
  /// loops. Each chain lists vertices; a loop repeats its first vertex last.
  std::vector<std::vector<int>> curves() const;

  int crossingCount() const { return crossingCount_; }
  const std::vector<Vec3>& nodes() const { return nodes_; }
  const std::vector<int>& adjacent(int v) const { return adjacent_[v]; }
  /// Moves vertex v (a junction that absorbs others).
  void moveNode(int v, const Vec3& x) { nodes_[v] = x; }

  /// The crossing that tells a chain's regions: its first vertex, unless that is a junction.
  int tagOf(const std::vector<int>& chain) const { return chain[chain[0] < crossingCount_ ? 0 : 1]; }

private:
  void addJunction(const Vec3& centre, const std::vector<int>& ending);

  double h_ = 0;
  int crossingCount_ = 0;
  std::vector<Vec3> nodes_;
  std::vector<std::vector<int>> adjacent_;
};
}
