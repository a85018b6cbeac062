// SPDX-License-Identifier: GPL-3.0-or-later
// The last resort of the dihedral-angle improvement: a new interior vertex on an interior edge,
// for tetrahedra that no flip mends and whose vertices cannot move (a thin layer between two
// interfaces, feature lines).
#pragma once

#include "ImprovementMesh.h"
#include "TetFlips.h"
#include "VertexMover.h"

#include <vector>

namespace omesh
{
/// Splits interior edges of an ImprovementMesh, keeping a split only where it pays.
class EdgeSplitter
{
public:
  /// `flips` finds the ring of an edge, `mover` places the new vertex; both work on `state`.
  EdgeSplitter(ImprovementMesh& state, const TetFlips& flips, VertexMover& mover);

  /// Splits interior edge ab at its midpoint (each tetrahedron around it in two), moves the new
  /// vertex to where its star is best and keeps it when the star's worst beats the ring's before;
  /// else everything goes back.
  bool splitEdge(int a, int b);

private:
  /// Where a new vertex on edge ab starts: its midpoint, or where that lies outside the material
  /// (a chord across a concave interface), the first point towards the centre of the ring that
  /// lies inside.
  Vec3 splitPoint(int a, int b, const std::vector<int>& ring, int material) const;

  ImprovementMesh& state_;
  const TetFlips& flips_;
  VertexMover& mover_;
  TetMesh& mesh_;
  TetStars& stars_;
  const HierarchicalOracle& oracle_;
};
}
