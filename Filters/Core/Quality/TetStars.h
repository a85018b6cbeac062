// SPDX-License-Identifier: GPL-3.0-or-later
// A tetrahedral mesh as the quality step edits it: tetrahedra added, removed and relabelled in
// place, each vertex knowing the live tetrahedra around it.
#pragma once

#include "TetMesh.h"

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace omesh
{
/// One key per undirected edge ab.
inline std::uint64_t edgeKey(int a, int b)
{
  const auto lo = static_cast<std::uint64_t>(std::min(a, b));
  const auto hi = static_cast<std::uint64_t>(std::max(a, b));
  return (hi << 32) | lo;
}

/// One key per triangle, whatever the order of its vertices.
struct FaceKey
{
  std::array<int, 3> v;
  FaceKey(int a, int b, int c)
    : v{ a, b, c }
  {
    std::sort(v.begin(), v.end());
  }
  bool operator==(const FaceKey& o) const { return v == o.v; }
};

struct FaceKeyHash
{
  std::size_t operator()(const FaceKey& k) const;
};

/// The tetrahedra as a mutable set: removed ones stay as tombstones until compact(), each vertex
/// lists the live tetrahedra around it.
class TetStars
{
public:
  explicit TetStars(const TetMesh& mesh);

  std::size_t size() const { return tets_.size(); }
  bool alive(int t) const { return alive_[static_cast<std::size_t>(t)] != 0; }
  const std::array<int, 4>& tet(int t) const { return tets_[static_cast<std::size_t>(t)]; }
  int material(int t) const { return material_[static_cast<std::size_t>(t)]; }
  void setMaterial(int t, int material) { material_[static_cast<std::size_t>(t)] = material; }
  const std::vector<int>& star(int v) const { return stars_[static_cast<std::size_t>(v)]; }

  int add(const std::array<int, 4>& t, int material);
  /// Takes back a removed tetrahedron (its vertices' stars list it again).
  void revive(int t);
  void remove(int t);

  /// Room for the star of a new vertex; the last one can be taken back while it has no tetrahedra.
  void addVertex() { stars_.emplace_back(); }
  void removeLastVertex() { stars_.pop_back(); }

  /// Live tetrahedra containing both a and b.
  std::vector<int> around(int a, int b) const;
  /// The live tetrahedron other than t with face abc, -1 when there is none (a boundary face).
  int beyond(int t, int a, int b, int c) const;

  /// Writes the live tetrahedra back, in their order (the new ones after the old).
  void compact(TetMesh& mesh) const;

private:
  std::vector<std::array<int, 4>> tets_;
  std::vector<int> material_;
  std::vector<unsigned char> alive_;
  std::vector<std::vector<int>> stars_;
};
}
