// SPDX-License-Identifier: GPL-3.0-or-later
// The last resort of the dihedral-angle improvement: a vertex of one interface merged into a
// neighbour on that interface, its star's tetrahedra gone or given the neighbour instead.
#pragma once

#include "ImprovementMesh.h"

#include <array>
#include <utility>
#include <vector>

namespace omesh
{
/// Edge collapses along interfaces on an ImprovementMesh. A thin tetrahedron whose four vertices
/// lie on a smooth interface (two faces on it, two inside its material) is flat whatever way it is
/// labelled and wherever its vertices slide along the interface: no flip, move, peel or interior
/// split removes it without breaking another bound. Removing one of its interface vertices does:
/// the vertex is merged into a neighbour on its interface, the tetrahedra around their edge go,
/// the rest of its star gets the neighbour instead (CGAL's Tetrahedral_remeshing collapses edges
/// the same way).
class InterfaceCollapse
{
public:
  explicit InterfaceCollapse(ImprovementMesh& state);

  /// Tries, for each vertex c of t that moves along one interface (both sides materials, its star
  /// closed), each neighbour u on that interface, and makes the collapse of c into u that leaves
  /// the best worst quality, when that beats the worst of c's star now. A collapse must keep the
  /// mesh a manifold (the link condition), every new tetrahedron positive and free of new flaws,
  /// no interface triangle twice, and the interface within the finer facet distance of its two
  /// materials of where c was. True when the mesh changed (c then belongs to no tetrahedron and
  /// ImprovementMesh::writeBack drops it).
  bool collapseAround(int t);

  /// Merges c into u when the rules above allow it (the quality aside: it need not pay); false
  /// and nothing changed when they do not.
  bool collapse(int c, int u);

private:
  /// The best quality the collapse of c into u leaves in c's star, -1 when it may not be done.
  double evaluate(int c, int u) const;
  void apply(int c, int u);
  /// c's star as the collapse of c into u leaves it: each tetrahedron not holding u (its id)
  /// with u for c.
  std::vector<std::pair<int, std::array<int, 4>>> replacedStar(int c, int u) const;
  /// The link condition of edge cu (Dey et al.): the vertices and edges that c's and u's links
  /// share are those of the edge's link.
  bool linkCondition(int c, int u) const;
  /// Whether the interface triangles of c, with u instead, pass within `reach` of c's position
  /// and none of them exists already.
  bool interfaceKept(int c, int u, double reach) const;

  ImprovementMesh& state_;
  TetMesh& mesh_;
  TetStars& stars_;
};
}
