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
  /// The plain sum over every triangle (for tests).
  double bruteForce(const Vec3& p) const;

  bool hasBorder() const { return !nodes_.empty() && nodes_[0].borderCount > 0; }

  /// An upper bound of |grad w| over `region` away from the triangles: off the surface the
  /// gradient of a solid angle is a line integral over the surface's border alone (Biot-Savart), so
  /// |grad w(x)| <= sum over border edges of length / (4 pi dist(x, edge)^2). Summed over clusters
  /// of border edges by box distance, edge by edge for clusters near the region; infinite where an
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
  int build(int first, int count);
  double evaluate(int node, const Vec3& p) const;

  std::vector<Vec3> points_;
  std::vector<std::array<int, 3>> triangles_; ///< reordered so that every node is a range
  std::vector<std::array<int, 2>> borders_;
  std::vector<Node> nodes_;
  double margin_ = 0.0;
  struct BorderCluster
  {
    BoundingBox box;
    double length = 0.0;
    int first = 0, count = 0; ///< its edges in clusterEdges_
  };
  std::vector<BorderCluster> clusters_;             ///< the root's border edges in spatial groups
  std::vector<std::array<int, 2>> clusterEdges_;    ///< those edges, cluster by cluster
};
}
