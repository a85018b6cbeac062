// SPDX-License-Identifier: GPL-3.0-or-later
// The flips of the dihedral-angle improvement: an interior edge removed (its ring of tetrahedra
// retriangulated the best way) and an interior face removed (2-3 flip). Each stays inside one
// material and off interfaces and feature edges, so the shapes the mesh must keep stay as they are.
#pragma once

#include "ImprovementMesh.h"

#include <vector>

namespace omesh
{
/// Edge and face removal on an ImprovementMesh, each only where it raises the worst quality of the
/// tetrahedra it touches (or, for removeEdge with `made`, where it is asked to).
class TetFlips
{
public:
  explicit TetFlips(ImprovementMesh& state);

  /// The ring of vertices around edge ab, ordered so that (a, b, r[i], r[i+1]) is positive, and the
  /// tetrahedra around it; false when the edge may not go (on a boundary, an interface or a feature
  /// line, between materials) or the ring is not closed.
  bool ringAround(int a, int b, std::vector<int>& ring, std::vector<int>& tets) const;

  /// Removes edge ab: its ring is triangulated the best way (Shewchuk's dynamic programme over the
  /// ring polygon), each triangle making one tetrahedron with a and one with b.
  /// With `made`: the edge goes even when that does not pay (as long as no tetrahedron is flat or
  /// inverted), and `made` receives the new tetrahedra, `removed` the ones removed.
  bool removeEdge(int a, int b, std::vector<int>* made = nullptr, std::vector<int>* removed = nullptr);

  /// 2-3 flip: face f of t and the same-material tetrahedron beyond it become three around the
  /// edge joining their apexes.
  bool removeFace(int t, int f);

private:
  ImprovementMesh& state_;
  TetStars& stars_;
};
}
