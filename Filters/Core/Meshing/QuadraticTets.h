// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include "TetMesh.h"

#include <array>
#include <map>
#include <string>
#include <vector>

namespace omesh
{
class HierarchicalOracle;

/// The six mid-edge nodes of a 10-node tetrahedron, in the order of VTK_QUADRATIC_TETRA and
/// Abaqus C3D10: nodes 4..9 sit on edges 01, 12, 20, 03, 13, 23.
constexpr int kQuadraticTetEdges[6][2] = { { 0, 1 }, { 1, 2 }, { 2, 0 }, { 0, 3 }, { 1, 3 }, { 2, 3 } };

/// Settings of makeQuadraticTets (internal tuning, not user-facing: the user chooses the order).
struct QuadraticOptions
{
  /// The snap search runs along the interface normal through the straight midpoint, up to this
  /// fraction of the edge length on each side (0.3: a half-circle chord bulges 0.5, a 30 degree arc 0.07).
  double searchFraction = 0.3;
  /// A curved tetrahedron whose smallest Jacobian determinant on the sample is below this fraction
  /// of its straight-sided one is relaxed (its moved mid-edge nodes pulled back by bisection).
  double minJacobianRatio = 0.2;
  /// Bisection steps per relaxation (the scale of the pulled-back displacements is found to 2^-steps).
  int bisectionSteps = 10;
};

/// A 10-node tetrahedral mesh made from a linear one.
struct QuadraticTetMesh
{
  std::vector<Vec3> points;        ///< the linear mesh's points, then one mid-edge node per edge
  std::vector<int> pointDimension; ///< as TetMesh's; a mid-edge node: 1 feature, 2 interface, 3 inside
  std::vector<std::array<int, 10>> tets; ///< same tetrahedra, positively oriented, VTK node order
  /// "quadratic.edges", "quadratic.interface_edges", "quadratic.snapped_nodes" (moved onto the
  /// interface), "quadratic.unsnapped_interface_edges" (junctions of three materials, non-manifold
  /// or creased interfaces, no crossing found in the search range: straight), "quadratic.feature_edges"
  /// (straight: they lie on the straight input segments), "quadratic.relaxed_nodes" (pulled back
  /// for validity), "quadratic.max_snap_distance" (relative to the edge length),
  /// "quadratic.min_jacobian_ratio" (the final mesh's smallest sampled det J / straight det J).
  std::map<std::string, double> statistics;
};

/// Adds a mid-edge node to every edge of `mesh`: on edges of faces between two materials (or a
/// material and the outside) the midpoint moves onto the oracle's true interface (the material change
/// nearest the straight midpoint along the faces' mean normal, within searchFraction of the edge
/// length); edges of constrained segments and interior edges stay straight. Then every curved
/// tetrahedron is checked on a sample of its Jacobian determinant (the 10 nodes and the 4 Gauss points
/// of the degree-2 rule) and, where the smallest is below minJacobianRatio times the straight
/// tetrahedron's, its moved nodes are pulled back towards their straight midpoints by bisection, in a
/// few passes over the mesh (a node pulled back can spoil a neighbour), ending with straight nodes where
/// that does not settle. Deterministic (sequential, in tetrahedron order).
QuadraticTetMesh makeQuadraticTets(
  const TetMesh& mesh, const HierarchicalOracle& oracle, const QuadraticOptions& options = {});

/// Jacobian determinant of the 10-node tetrahedron `nodes` (VTK order) at barycentric coordinates
/// `l` (l[0] for corner 0, ..., summing to 1): 6 x the signed volume for straight sides.
double quadraticTetJacobian(const std::array<Vec3, 10>& nodes, const std::array<double, 4>& l);

/// Smallest Jacobian determinant on the sample (10 nodes, 4 Gauss points) divided by that of the
/// straight-sided tetrahedron on the same corners; 1 for straight sides, <= 0 when inverted somewhere.
/// -infinity for a flat corner tetrahedron.
double quadraticTetJacobianRatio(const std::array<Vec3, 10>& nodes);

/// Volume of the 10-node tetrahedron (exact: a degree-3 rule on the cubic Jacobian).
double quadraticTetVolume(const std::array<Vec3, 10>& nodes);
}
