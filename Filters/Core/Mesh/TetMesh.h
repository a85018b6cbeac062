// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include "Vec3.h"

#include <array>
#include <cstddef>
#include <map>
#include <string>
#include <vector>

namespace omesh
{
/// The mesher's output: tetrahedra with a material each, the interface triangles between
/// materials (and the outside) and the constrained segments as they stand in the mesh.
struct TetMesh
{
  std::vector<Vec3> points;
  std::vector<int> pointDimension; ///< 0 corner, 1 on a segment, 2 on an interface, 3 inside
  std::vector<std::array<int, 4>> tets;
  std::vector<int> tetMaterial;
  std::vector<unsigned char> tetDefects; ///< TetDefect bits per tetrahedron (MeshValidity.h), when checked

  /// A tetrahedron's face on the mesh's boundary or between two materials, kept on the side of its
  /// owner: the lower material id (the finite-element writers' surface sets).
  struct SeparatingFace
  {
    std::size_t tet = 0; ///< the owner
    int opposite = 0;    ///< its corner (0-3, in `tets` order) not on the face
    int other = -1;      ///< the material on the other side, -1 outside
  };
  /// The separating faces as the validity check found them from the tetrahedra alone (when asked).
  std::vector<SeparatingFace> separatingFaces;

  std::vector<std::array<int, 3>> interfaceTriangles;
  std::vector<std::array<int, 2>> interfaceMaterials; ///< material on each side (-1 outside)

  /// Constrained segments after meshing: each input segment cut at the mesh vertices lying on it;
  /// a piece is `present` when its two ends are mesh vertices joined by a tetrahedron edge, or
  /// lies on an edge that runs straight through the input points ending it (locateFeatureSegments).
  struct Segment
  {
    Vec3 a, b;
    int aId = -1, bId = -1; ///< mesh point ids of the ends, -1 where an end is no mesh vertex
    /// index of the input segment it belongs to: of the lines given to the mesher, also when it
    /// resampled them (the given segment its resampled one came from, FeatureSegments::source)
    int input = -1;
    bool present = false;
  };
  std::vector<Segment> segments;

  /// Statistics and timings by name ("time.refine", "segment_splits", ...).
  std::map<std::string, double> statistics;
  std::vector<std::string> warnings;
};
}
