// SPDX-License-Identifier: GPL-3.0-or-later
// The mesh as the dihedral-angle improvement edits it: the live tetrahedra around each vertex,
// which vertices may move and how, the interface triangles by face, the measures every local
// change is judged by, and the report the changes count into. The local changes (TetFlips,
// VertexMover, EdgeSplitter, SliverPeeler) share one, so each can be run and tested on its own.
#pragma once

#include "DihedralImprovement.h"
#include "TetStars.h"

#include <array>
#include <cstddef>
#include <cstdint>
#include <unordered_map>
#include <unordered_set>
#include <vector>

namespace omesh
{
class HierarchicalOracle;

/// How a vertex may move.
enum class VertexKind : unsigned char
{
  Fixed,
  Interior,
  Interface,
  OnLine ///< inside one straight feature segment: slides along it
};

/// A face of a peeled tetrahedron: off every interface (`gone`), or on one between `materials`.
struct Retriangulated
{
  std::array<int, 3> tri;
  std::array<int, 2> materials;
  bool gone;
};

/// What ImprovementMesh::swapInterfaces changed, for undoSwap.
struct InterfaceSwap
{
  std::vector<int> gone, made;
  std::vector<std::pair<int, VertexKind>> kinds;
};

/// The tetrahedra of a TetMesh as a mutable set (TetStars), with what the dihedral-angle
/// improvement needs to judge a change: the window quality, the flaws that keep a tetrahedron out
/// of the mesh, the kind of every vertex, the kept feature edges and the interface triangles.
/// writeBack() puts the result into the TetMesh.
class ImprovementMesh
{
public:
  /// Classifies the vertices of `mesh` (its segments located, locateFeatureSegments). `oracle` and
  /// `options` must outlive this.
  ImprovementMesh(TetMesh& mesh, const HierarchicalOracle& oracle, const DihedralImprovementOptions& options);

  TetMesh& mesh() { return mesh_; }
  const TetMesh& mesh() const { return mesh_; }
  TetStars& stars() { return stars_; }
  const TetStars& stars() const { return stars_; }
  const HierarchicalOracle& oracle() const { return oracle_; }
  const DihedralImprovementOptions& options() const { return options_; }
  /// The counters the changes add to.
  DihedralImprovementReport& report() { return report_; }
  /// Tetrahedra made or moved in this round (the driver's candidates for the next).
  std::vector<int>& touched() { return touched_; }

  // --- measures ----------------------------------------------------------------------------
  /// dihedralWindowQuality of t, -1 when it is flat or inverted.
  double quality(const std::array<int, 4>& t) const;
  double quality(int t) const { return quality(stars_.tet(t)); }
  /// Signed volume in the mesh's orientation (positive for its tetrahedra).
  double orient(const std::array<int, 4>& t) const;
  double longestEdge(const std::array<int, 4>& t) const;
  /// The worst quality of `tets`.
  double worstOf(const std::vector<int>& tets) const;
  /// The worst quality of v's star; `worst` gets its tetrahedron.
  double starQuality(int v, int* worst = nullptr) const;
  /// Tetrahedra outside the window and the extreme angles; with `held`, the outside ones whose
  /// vertices are all held.
  void measure(std::size_t& outside, double& minAngle, double& maxAngle, std::size_t* held = nullptr) const;

  /// What keeps tetrahedron t of `material` out of the mesh (Flaw bits, 0 = nothing): micro (the
  /// checks would call it so, MeshValidity.h, whatever its angles), larger than `sizeFactor` x
  /// its material's cell size, or, with all four vertices on interfaces or feature lines, its
  /// centroid in another material.
  unsigned flaws(const std::array<int, 4>& t, int material, double sizeFactor = 1.0) const;
  bool acceptable(const std::array<int, 4>& t, int material) const { return flaws(t, material) == 0; }
  /// Whether the tetrahedra around v are acceptable; with `flawsBefore` (one set per star
  /// tetrahedron, taken before a move), a move need not mend what it found: a tetrahedron already
  /// larger than its cell size may stay so, one already below the micro length must stay above
  /// the floor; one already across a boundary may not be moved (it could only go further).
  bool starAcceptable(int v, const std::vector<unsigned>* flawsBefore = nullptr) const;
  /// Of the flaws a tetrahedron had before a change, those its replacement may keep (larger than
  /// the cell size, short; not across a boundary).
  static unsigned tolerableFlaws(unsigned before);

  /// Adds a tetrahedron and remembers it for the next round.
  int addTet(const std::array<int, 4>& t, int material);

  // --- what may change -----------------------------------------------------------------------
  VertexKind kind(int v) const { return kind_[static_cast<std::size_t>(v)]; }
  /// The two materials of an interface vertex (the smaller first).
  const std::array<int, 2>& sides(int v) const { return sides_[static_cast<std::size_t>(v)]; }
  /// The interface triangles at v (indices in mesh().interfaceTriangles).
  const std::vector<int>& interfacesAt(int v) const { return interfaceAt_[static_cast<std::size_t>(v)]; }
  /// The unit direction of an OnLine vertex's segment.
  const Vec3& lineDirection(int v) const { return lineDirection_.at(v); }
  /// Whether edge ab is a feature edge (a present segment piece, or a chord between two feature
  /// vertices): it stays.
  bool isKept(int a, int b) const;
  bool isInterface(int a, int b, int c) const { return interfaces_.count(FaceKey(a, b, c)) != 0; }

  /// A new interior vertex at x (its star empty); removeLastVertex takes it back while its star is.
  void addInteriorVertex(const Vec3& x);
  void removeLastVertex();
  /// Vertex v no longer belongs to any tetrahedron (collapsed): held, and dropped from the mesh's
  /// points by writeBack (the indices after it shift down).
  void dropVertex(int v);

  /// The interface triangles of `changes` that were on an interface go; those not `gone` come
  /// (again) with their materials. Vertices of one interface that now touch another are held.
  InterfaceSwap swapInterfaces(const std::vector<Retriangulated>& changes);
  void undoSwap(const InterfaceSwap& swap);

  /// Writes the live tetrahedra, the interface triangles left and the segment ends (which may have
  /// slid along their lines) back to the mesh, without the dropped vertices.
  void writeBack();

private:
  /// The validity check's length (validityLength, MeshValidity.h), with the median of one edge per
  /// tetrahedron.
  double typicalEdge() const;
  double orientationOfMesh() const;
  /// Interface triangles and feature edges are kept; vertices on one interface move along it,
  /// interior vertices anywhere, the others stay.
  void classifyVertices();
  /// A segment point between two present pieces of the same straight segment (not an input point)
  /// slides along it: its edges stay on the line.
  void classifyLineVertices();
  VertexKind classifyFree(int v) const;
  /// Drops the peeled interface triangles from the mesh.
  void compactInterfaces();
  /// Drops the collapsed vertices from the mesh's points, renumbering what refers to points.
  void compactPoints();

  TetMesh& mesh_;
  const HierarchicalOracle& oracle_;
  const DihedralImprovementOptions& options_;
  TetStars stars_;
  double orientation_ = 1.0;
  double microLength_ = 0.0; ///< no tetrahedron is made whose longest edge is shorter
  std::vector<VertexKind> kind_;
  std::vector<std::array<int, 2>> sides_;      ///< the two materials of an interface vertex
  std::vector<std::vector<int>> interfaceAt_;  ///< interface triangles at each vertex
  std::unordered_set<std::uint64_t> kept_;     ///< present feature-segment edges
  std::unordered_map<int, Vec3> lineDirection_; ///< of each OnLine vertex's segment (unit)
  std::unordered_map<FaceKey, int, FaceKeyHash> interfaces_; ///< -> index in mesh_.interfaceTriangles
  std::vector<unsigned char> interfaceGone_;                 ///< per interface triangle: peeled away
  DihedralImprovementReport report_;
  std::vector<int> touched_; ///< tetrahedra made or moved in this round
  std::vector<int> dropped_; ///< collapsed vertices (dropVertex)
};
}
