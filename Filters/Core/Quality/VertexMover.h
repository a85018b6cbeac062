// SPDX-License-Identifier: GPL-3.0-or-later
// The vertex moves of the dihedral-angle improvement: a vertex goes where the worst tetrahedron of
// its star is best, an interior vertex anywhere inside its material, an interface vertex along its
// interface (put back on it by the oracle), a vertex inside a straight feature segment along it.
#pragma once

#include "ImprovementMesh.h"

#include <vector>

namespace omesh
{
/// Moves vertices of an ImprovementMesh by gradient ascent on their star's worst quality.
class VertexMover
{
public:
  explicit VertexMover(ImprovementMesh& state);

  /// Gradient ascent on the star's worst quality (numerical gradient of the worst tetrahedron,
  /// halving steps until the star's worst rises); interface vertices move in the tangent plane and
  /// are put back on the interface. True when v moved (counted in the report, its star touched).
  bool moveVertex(int v);

private:
  /// A vertex being moved: where it may go and how good its star is.
  struct Step
  {
    int v;
    VertexKind kind;
    Vec3 normal;   ///< of its interface (Interface vertices move in the tangent plane)
    double length; ///< mean edge length around it
    int material;  ///< of its tetrahedra (an interior vertex's)
    double current;
    int worst;
    const std::vector<unsigned>& flawsBefore;
  };

  double meanEdgeLength(int v) const;
  /// Unit normal of the interface at v, pointing from sides(v)[0] to sides(v)[1] (area-weighted
  /// mean of its interface triangles'); zero when they do not agree on a side.
  Vec3 interfaceNormal(int v) const;
  /// x put back on v's interface: the change from sides(v)[0] to sides(v)[1] along `normal`
  /// within `reach`; false when there is none.
  bool onInterface(int v, const Vec3& normal, double reach, Vec3& x) const;
  /// Moves s.v along `direction` (in the tangent plane for an interface vertex, then put back on
  /// the interface) by the longest of 0.2, 0.1, ... x the edge length that raises its star's worst
  /// quality; false (and the vertex where it was) when none does.
  bool lineSearch(Step& s, Vec3 direction);
  /// Central-difference gradient of tetrahedron t's quality with respect to vertex v's position.
  Vec3 gradient(int t, int v, double h);

  ImprovementMesh& state_;
  TetMesh& mesh_;
  TetStars& stars_;
  const HierarchicalOracle& oracle_;
};
}
