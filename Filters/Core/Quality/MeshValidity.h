// SPDX-License-Identifier: GPL-3.0-or-later
// What a finite-element code rejects in a tetrahedral mesh, counted independently of how the mesh
// was made. Run by the mesher on every mesh it returns, and on demand on any mesh.
#pragma once

#include "ShapeSummary.h"
#include "TetMesh.h"

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

namespace omesh
{
/// The length L the thresholds are relative to: the median edge, or the edge of a regular
/// tetrahedron of the mean volume (`totalVolume` / `tetrahedra`) where that is longer (a cluster of
/// tiny tetrahedra that is most of the mesh must not pull L down with it).
double validityLength(double medianEdge, double totalVolume, std::size_t tetrahedra);

struct ValidityThresholds
{
  double duplicate = 1e-9; ///< two used vertices closer than this x L are duplicates
  double micro = 1e-4;     ///< a tetrahedron whose longest edge is below this x L is micro
  double flat = 1e-8;      ///< a tetrahedron with |volume| below this x (longest edge)^3 is flat
  bool segmentsRequired = true; ///< count TetMesh::segments pieces that are not mesh edges
  /// The facet distance of a material (<= 0: none). When given, tetrahedra with every vertex on
  /// an interface or feature line whose centroid lies in another material are counted as lying
  /// across a boundary (MeshValidity::acrossBoundary*) if their smallest altitude (how far they
  /// reach across) exceeds acrossBoundaryLength of the two materials: thinner ones misplace the
  /// boundary by less than the facet criterion allows.
  std::function<double(int)> facetDistanceOf;
};

/// The length above which a tetrahedron of material `a` whose centroid lies in material `b` counts as
/// across a boundary, from their facet distances (<= 0: none): the smaller one; 0 (never) when
/// neither has one. The mesher's refinement uses the same rule (MaterialCellCriterion).
inline double acrossBoundaryLength(double a, double b)
{
  return a > 0 && b > 0 ? (a < b ? a : b) : a > 0 ? a : b > 0 ? b : 0.0;
}

/// How far tetrahedron abcd of material `own` is known to reach across a boundary: the length of
/// acrossBoundaryLength for `own` and the material at its centroid when that material differs,
/// the smallest altitude exceeds the length, and that material also holds half way from the
/// centroid to each vertex (the tetrahedron lies in it, not across a thin layer of it: a lamina of
/// a label map thinner than the tetrahedron misplaces the boundary by less); else 0. Whether the
/// vertices lie on interfaces is the caller's test. Used by the validity check and by the
/// mesher's label rule alike.
double acrossBoundaryBy(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, int own,
  const std::function<double(int)>& facetDistanceOf, const std::function<int(const Vec3&)>& materialAt);

/// Defect counts of one mesh; every count is a defect except where noted.
struct MeshValidity
{
  std::size_t duplicateVertices = 0;  ///< used vertices with another used vertex closer than duplicate x L
  std::size_t microTetrahedra = 0;    ///< longest edge < micro x L
  std::size_t flatTetrahedra = 0;     ///< |volume| < flat x longest edge^3 (includes zero volume)
  std::size_t invertedTetrahedra = 0; ///< negative signed volume (VTK's and CGAL's orientation)
  std::size_t nonManifoldFaces = 0;   ///< triangles shared by more than two tetrahedra
  std::size_t badIndices = 0;         ///< tetrahedra with an out-of-range or repeated vertex index
  /// Tetrahedra whose four vertices all lie inside a material (dimension 3) but whose centroid the
  /// oracle puts in another material: an interface passes through them unsampled (a missed thin
  /// layer) or they carry the wrong material. Needs the oracle; tetrahedra touching an interface
  /// are not counted (their centroid may lie across a curved interface within the facet distance).
  std::size_t materialMismatches = 0;
  /// Pieces of the constrained segments (TetMesh::segments) that are not mesh edges.
  std::size_t missingSegmentPieces = 0;
  /// Points no tetrahedron uses: nodes without an element leave a zero row in a stiffness matrix
  /// (a singular system) or are refused by finite-element codes.
  std::size_t unusedVertices = 0;

  /// Not a defect (the elements are sound), a fidelity figure: tetrahedra whose vertices all lie
  /// on interfaces or feature lines but whose centroid the oracle puts in another material, thicker
  /// (smallest altitude) than acrossBoundaryLength of the two materials (ValidityThresholds::facetDistanceOf): they fill a part of a material with another
  /// (at an acute edge, cells from one face to the other labelled by a circumcentre outside).
  std::size_t acrossBoundaryTetrahedra = 0;
  double acrossBoundaryVolume = 0.0; ///< their volume

  double medianEdge = 0.0;     ///< not a defect (L is at least this)
  double shortestEdge = 0.0;   ///< not a defect

  std::size_t defects() const
  {
    return duplicateVertices + microTetrahedra + flatTetrahedra + invertedTetrahedra + nonManifoldFaces +
      badIndices + materialMismatches + missingSegmentPieces + unusedVertices;
  }
  bool valid() const { return defects() == 0; }
  /// "3 duplicate vertices, 12 micro tetrahedra" (empty when valid).
  std::string describe() const;
  /// (statistic name, value) pairs, names "validity.<defect>", for TetMesh::statistics.
  std::vector<std::pair<std::string, double>> asStatistics() const;
};

/// Bits of a tetrahedron's defects (see checkMeshValidity's `tetDefects`).
enum TetDefect : unsigned char
{
  kDuplicateVertex = 1,  ///< one of its vertices is a duplicate
  kMicro = 2,
  kFlat = 4,
  kInverted = 8,
  kNonManifoldFace = 16, ///< one of its faces is shared by more than two tetrahedra
  kBadIndices = 32,
  kMaterialMismatch = 64
};

/// What the validity check gives besides its counts, from the passes it makes anyway: the mesher's
/// one pass over the tetrahedra after refinement and the writers' surface sets need no pass of their
/// own.
struct ValidityByproducts
{
  /// the faces of one tetrahedron only or of two of different materials, found by the pass that
  /// looks for faces of more than two (in the order of their vertices, smallest first)
  std::vector<TetMesh::SeparatingFace>* separatingFaces = nullptr;
  /// each tetrahedron's TetShape (as summariseShapes measures it) summarised here
  ShapeSummary* shapes = nullptr;
  /// and written here, with `shapes` (0 for a tetrahedron with bad indices)
  TetShapeArrays shapeArrays;
};

/// Checks `mesh` (tets, tetMaterial, points, segments). `materialAt` (may be empty) is the
/// oracle's material at a point, for the material check; `pointDimension` is used when present.
/// `tetDefects`, when given, receives a TetDefect bit set per tetrahedron.
MeshValidity checkMeshValidity(const TetMesh& mesh, const std::function<int(const Vec3&)>& materialAt = {},
  const ValidityThresholds& thresholds = {}, std::vector<unsigned char>* tetDefects = nullptr,
  const ValidityByproducts& byproducts = {});
}
