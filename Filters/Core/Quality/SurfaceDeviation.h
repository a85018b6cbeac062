// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include "SurfaceDomain.h"
#include "TetMesh.h"

#include <string>

namespace omesh
{
/// How far a material's boundary in the mesh and the surface it was meshed from lie apart: both
/// one-sided Hausdorff distances, at the vertices (of the boundary, of the input surface).
struct SurfaceDeviation
{
  size_t boundaryTriangles = 0; ///< faces of the material's tetrahedra that no other of them shares
  double meshToInput = 0.0;     ///< largest distance of a boundary vertex from the input surface
  Vec3 meshToInputAt;           ///< that vertex
  double inputToMesh = 0.0;     ///< largest distance of an input vertex from the boundary
  Vec3 inputToMeshAt;           ///< that vertex

  /// "the mesh's boundary lies up to 0.8 from the input surface (at (1, 2, 3)), the input up to
  /// 0.02 from the boundary (at (4, 5, 6))".
  std::string describe() const;
};

/// The deviation between `material`'s boundary in `mesh` (the faces of its tetrahedra that no
/// other of them shares) and `surface`.
/// Where other domains take over part of the surface, the input lies farther from the boundary
/// there. Zero distances when the material has no boundary.
SurfaceDeviation surfaceDeviation(const TetMesh& mesh, int material, const SurfaceDomain& surface);
}
