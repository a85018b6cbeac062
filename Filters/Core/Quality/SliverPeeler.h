// SPDX-License-Identifier: GPL-3.0-or-later
// Peeling in the dihedral-angle improvement: a thin tetrahedron on a fold of an interface goes over
// to the other side, moving the interface by at most its height. The only change that reaches a
// tetrahedron whose vertices are all held (on feature lines, corners, where interfaces meet).
#pragma once

#include "ImprovementMesh.h"
#include "TetFlips.h"
#include "VertexMover.h"

#include <array>
#include <vector>

namespace omesh
{
/// Peels thin tetrahedra off the interfaces of an ImprovementMesh.
class SliverPeeler
{
public:
  /// `flips` and `mover` mend the material a tetrahedron is given to; all work on `state`.
  SliverPeeler(ImprovementMesh& state, TetFlips& flips, VertexMover& mover);

  /// A thin tetrahedron lying on a fold of an interface (every vertex on an interface, two faces
  /// on it towards the same side X, the edge between its other two faces inside its own material)
  /// goes over to X: the outside (it is removed) or the material beyond (and the edge it leaves
  /// inside X is removed, else it goes back). The interface then runs through its other two
  /// faces, at most its height away (CGAL's Tetrahedral_remeshing peels slivers the same way).
  /// Tetrahedra whose vertices are all held are reached this way only.
  bool peel(int t);

private:
  static std::array<int, 3> face(const std::array<int, 4>& q, int f);
  /// Whether edge cd is inside material m: every tetrahedron around it of m, no face around it on
  /// an interface or the boundary.
  bool insideOneMaterial(int c, int d, int m) const;
  /// Whether the tetrahedra around edge cd close around it (no face at it on the boundary).
  bool closedAround(int c, int d) const;
  /// Tetrahedron t leaves the mesh; its faces towards the outside go, the others become the
  /// boundary.
  bool removeToOutside(int t, std::vector<Retriangulated>& changes);
  /// Tetrahedron t goes from its material to x; kept when a flip inside x then removes it, or
  /// when removing its fold edge ab and moving the vertices around it does.
  bool giveTo(int t, int x, int a, int b, std::vector<Retriangulated>& changes);
  /// Removes edge ab although that alone does not pay, then moves the vertices of its ring; kept
  /// when the new tetrahedra end better than `before`, else everything goes back.
  bool removeEdgeAndMove(int a, int b, double before);

  ImprovementMesh& state_;
  TetFlips& flips_;
  VertexMover& mover_;
  TetMesh& mesh_;
  TetStars& stars_;
};
}
