// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include "BoundingBox.h"
#include "Vec3.h"

#include <array>
#include <vector>

namespace omesh
{
/// Generalized winding number of an oriented triangle soup (Jacobson et al. 2013; fTetWild's
/// inside test): the signed solid angle the triangles subtend at a point, over 4 pi. It is 1 inside
/// and 0 outside a closed outward surface and varies smoothly across holes, so "inside where it
/// exceeds 1/2" closes small holes and borders the way a user expects.
///
/// Evaluation is hierarchical and exact up to rounding: a bounding-volume tree over the
/// triangles; for a node whose box does not contain the point, its triangles plus a fan from the
/// box centre to its border edges form a closed surface that does not wind around the point, so
/// the node contributes exactly the fan's solid angle (with the opposite sign), which costs one
/// term per border edge of the node instead of one per triangle.
class WindingNumber
{
public:
  WindingNumber() = default;
  /// `triangles` must be oriented consistently (outward for a closed surface) with valid indices.
  WindingNumber(const std::vector<Vec3>& points, const std::vector<std::array<int, 3>>& triangles);

  /// The winding number at p (about 0.5 on the surface itself).
  double operator()(const Vec3& p) const;
  /// The winding number at p with the nodes far from p (their area centroid more than 2 of their
  /// radii away) taken by a second-order expansion of their solid angle (Barill et al. 2018, as
  /// libigl's and fTetWild's fast winding number): about ten times cheaper than operator() on a
  /// 100k-triangle surface. The nodes near p and their triangles are summed exactly, so it jumps
  /// by 1 across a triangle as operator() does. Its error is not bounded rigorously (a rigorous
  /// bound of the remainder is some thousand times the error and would decide nothing):
  /// measured at most 7e-3 (`kApproximationError`, 1/16, leaves a margin of nine).
  double approximate(const Vec3& p) const;
  static constexpr double kApproximationError = 0.0625;
  /// The plain sum over every triangle (for tests).
  double bruteForce(const Vec3& p) const;

  bool hasBorder() const { return !nodes_.empty() && nodes_[0].borderCount > 0; }

  /// An upper bound of |grad w| over `region` away from the triangles: off the surface the
  /// gradient of a solid angle is a line integral over the surface's border alone (Biot-Savart), so
  /// |grad w(x)| <= sum over border edges of length / (4 pi dist(x, edge)^2). Summed over a tree
  /// of the border edges, a node far from the region as a whole, edge by edge near it; two border edges
  /// that run opposite ways with ends at most a third of their length apart (an unwelded seam, a
  /// jittered soup) count as a pair, by their gap eps: 2 eps / r^2 + 2 L eps / r^3; infinite where an
  /// edge may meet the region, 0 for a closed surface. Between two points joined by a segment that crosses no triangle, w changes by
  /// at most this bound times their distance.
  double gradientBound(const BoundingBox& region) const;

private:
  struct Node
  {
    BoundingBox box;
    Vec3 centre;
    int child[2] = { -1, -1 };
    int first = 0, count = 0;             ///< triangles [first, first + count) of order_
    int borderFirst = 0, borderCount = 0; ///< directed border edges of the node's triangles
  };
  /// A node's triangles seen from afar: about their area centroid, the moments of n dA (n the unit
  /// normal) of order 0 to 2, the radius of a ball around the centroid holding them, their area.
  struct FarField
  {
    Vec3 centre;
    double radius = 0.0, area = 0.0;
    Vec3 normal;                     ///< sum of n dA
    std::array<double, 9> first{};   ///< [j][k]: sum of n_j (x - centre)_k dA
    std::array<double, 18> second{}; ///< [j][kl], kl = xx yy zz xy xz yz: sum of n_j (x - c)_k (x - c)_l dA
  };
  int build(int first, int count, std::vector<FarField>& far);
  /// Stores the node's border from `edges` (its triangles' or its children's border edges).
  void setBorder(int node, std::vector<std::array<int, 2>>& edges);
  void buildFarField(const Node& node, FarField& far) const;
  static FarField mergedFarField(const FarField& a, const FarField& b, const Vec3& boxCentre);
  double evaluate(int node, const Vec3& p) const;
  double approximate(int node, const Vec3& p) const;

  std::vector<Vec3> points_;
  std::vector<std::array<int, 3>> triangles_; ///< reordered so that every node is a range
  std::vector<std::array<int, 2>> borders_;
  std::vector<Node> nodes_;
  /// FarField as approximate() reads it, one per node: the test for "far" first, the moments in
  /// single precision (their rounding, ~1e-7 relative, is far below the expansion's error)
  struct Expansion
  {
    Vec3 centre;
    double farRadius2 = 0.0;   ///< squared distance beyond which the node is far
    std::array<float, 30> moments{}; ///< normal (3), first (9), second (18)
  };
  std::vector<Expansion> expansions_;
  double margin_ = 0.0;
  /// A border edge, or a pair of border edges running opposite ways at most `gap` apart.
  struct BorderItem
  {
    std::array<int, 2> edge{};
    std::array<int, 2> partner{ -1, -1 };
    double gap = 0.0;
  };
  std::vector<BorderItem> pairedBorder() const;
  /// The root's border as items in a tree, for gradientBound.
  void indexBorder();
  /// A tree over the root's border items: per node the unpaired edges' length, the pairs' gaps and
  /// gaps x lengths, for the bound of far nodes as a whole.
  struct BorderNode
  {
    BoundingBox box;
    double length = 0.0, gap = 0.0, gapLength = 0.0;
    int first = 0, count = 0; ///< its items in borderItems_
    int child[2] = { -1, -1 };
  };
  int buildBorderTree(int first, int count);
  double borderBound(int node, const BoundingBox& region, const Vec3& centre, double reach) const;
  std::vector<BorderItem> borderItems_;
  std::vector<BorderNode> borderTree_;
};
}
