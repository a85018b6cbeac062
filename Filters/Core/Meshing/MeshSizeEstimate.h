// SPDX-License-Identifier: GPL-3.0-or-later
// How big a mesh the criteria ask for, before any meshing: for refusing, with a clear message, a
// run whose mesh cannot fit in memory (issue 14: tiny criteria used to end in std::bad_alloc or
// the kernel's OOM killer after minutes).
#pragma once

#include "FeatureSegments.h"
#include "MeshCriteria.h"

namespace omesh
{
class HierarchicalOracle;

/// Peak bytes per mesh vertex of a meshing run (triangulation, complex, optimisers, the output
/// mesh and its VTK copy): measured 662 bytes per tetrahedron at ~1M tetrahedra (issue 12's peer
/// benchmark) at about 6 tetrahedra per vertex, rounded up.
constexpr double kBytesPerMeshVertex = 4096.0;

/// A generous estimate of the vertices the criteria ask for: per material, its volume over the cell
/// size cubed; its interfaces' area over the facet size squared; the feature lines' length over
/// their edge size (each segment's, resolveFeatureEdgeSizes). Volumes and areas come from sampling the oracle on a grid (24 cells along each axis),
/// so the estimate is rough (within a small factor), which is enough to tell a mesh that fits in
/// memory from one of 10^12 vertices. Criteria that are unset count as 1/20 of the diagonal.
double estimateMeshVertices(const HierarchicalOracle& oracle, const MaterialCriteria& criteria,
  const FeatureSegments& features);

/// The volume part alone (each material's volume over its cell size cubed): what the mesher's
/// progress expects of refinement.
double estimateCellVertices(const HierarchicalOracle& oracle, const MaterialCriteria& criteria);
}
