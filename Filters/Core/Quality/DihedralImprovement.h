// SPDX-License-Identifier: GPL-3.0-or-later
// The quality step after refinement: local changes that bring every dihedral angle into a window.
#pragma once

#include "TetMesh.h"

#include <cstddef>
#include <functional>

namespace omesh
{
class HierarchicalOracle;

struct DihedralImprovementOptions
{
  double minAngle = 15.0;  ///< degrees: the window's lower end
  double maxAngle = 155.0; ///< degrees: the window's upper end
  /// Rounds over the tetrahedra outside the window, worst first; a round that changes nothing ends
  /// the step. A budget of steps, not seconds: a seed gives the same mesh on any machine.
  int rounds = 6;
  /// The circumradius bound of a material's tetrahedra (its cell size; <= 0: none): no change
  /// makes a tetrahedron larger than its material allows. Unset: no bound.
  std::function<double(int)> cellSizeOf;
  /// The facet distance of a material (<= 0: none): an interface collapse moves the interface by
  /// no more than the finer of its two materials'. Unset: 1/20 of the collapsed edge.
  std::function<double(int)> facetDistanceOf;
  /// Called between tetrahedra with the fraction of the work done (may throw to abort).
  std::function<void(double)> progress;
};

struct DihedralImprovementReport
{
  std::size_t outsideBefore = 0; ///< tetrahedra with an angle outside the window, before and after
  std::size_t outsideAfter = 0;
  /// of those after, the ones whose four vertices are all held (on feature lines, corners, where
  /// interfaces meet): their shape is the input's lines', no move or interior flip reaches them
  std::size_t outsideHeld = 0;
  double minBefore = 0.0, maxBefore = 0.0; ///< extreme dihedral angles (degrees)
  double minAfter = 0.0, maxAfter = 0.0;
  std::size_t edgeRemovals = 0;   ///< interior edges removed (3-2 flips and larger rings)
  std::size_t faceRemovals = 0;   ///< interior faces removed (2-3 flips)
  std::size_t edgeSplits = 0;     ///< interior vertices added on interior edges (kept ones)
  std::size_t peeled = 0;         ///< thin tetrahedra on a fold of an interface given to the other side
  std::size_t interfaceCollapses = 0; ///< interface vertices merged into a neighbour on their interface
  std::size_t interiorMoves = 0;  ///< interior vertices moved
  std::size_t surfaceMoves = 0;   ///< interface vertices moved along their interface (kept on it)
  std::size_t lineMoves = 0;      ///< feature-line vertices moved along their straight segment
  int rounds = 0;                 ///< rounds run
  bool cutShort = false;          ///< the round budget ended it with work left that still paid
};

/// Raises the worst tetrahedra of `mesh` towards every dihedral angle in
/// [options.minAngle, options.maxAngle], by changes that each raise the worst quality of the
/// tetrahedra they touch (quality: the smallest of angle / minAngle and (180 - angle) /
/// (180 - maxAngle) over the six angles; 1 at the window's ends):
///  - removing an interior edge (its ring of tetrahedra retriangulated, the best of all ways) or an
///    interior face (2-3 flip), only inside one material and never an edge of a feature line, so
///    interface triangles and feature edges stay as they are;
///  - moving an interior vertex to where its star's worst tetrahedron is best;
///  - where nothing else helps, splitting an interior edge of the tetrahedron (a new interior
///    vertex, moved the same way, kept only when it raises the worst of its star);
///  - moving a vertex of exactly one interface (two materials, or a material and the outside) along
///    it, each trial point put back on the oracle's interface (HierarchicalOracle::intersect along
///    the interface normal);
///  - as the last resort, merging a vertex of one interface between two materials into a
///    neighbour on it (InterfaceCollapse.h): the vertex leaves the mesh.
/// No change makes a tetrahedron larger than its material's cell size, nor one whose four vertices
/// all lie on interfaces or feature lines with its centroid in another material (an edge across a
/// thin or acute part). A vertex inside one straight feature segment (between two present pieces
/// of it, not an input point) moves only along it; other vertices on feature lines, corners and
/// vertices where interfaces meet do not move. Deterministic. mesh.segments must be
/// located (locateFeatureSegments) before: their present pieces are the edges kept.
DihedralImprovementReport improveDihedralAngles(
  TetMesh& mesh, const HierarchicalOracle& oracle, const DihedralImprovementOptions& options = {});

/// The quality used above: min over the six dihedral angles of min(angle / minAngle,
/// (180 - angle) / (180 - maxAngle)); at least 1 exactly when every angle lies in the window;
/// -1 for a flat tetrahedron.
double dihedralWindowQuality(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, double minAngle,
  double maxAngle);
}
