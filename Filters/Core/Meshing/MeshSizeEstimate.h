// SPDX-License-Identifier: GPL-3.0-or-later
// How big a mesh the criteria ask for, before any meshing: for refusing, with a clear message, a
// run whose mesh cannot fit in memory (tiny criteria would otherwise end in std::bad_alloc or the
// kernel's OOM killer after minutes).
#pragma once

#include "FeatureSegments.h"
#include "MeshCriteria.h"

#include <string>
#include <vector>

namespace omesh
{
class HierarchicalOracle;

/// Peak bytes per mesh vertex of a meshing run (triangulation, complex, optimisers, the output
/// mesh and its VTK copy): about 660 bytes per tetrahedron at ~1M tetrahedra (Benchmarks/peer_benchmark.py) at
/// about 6 tetrahedra per vertex, rounded up.
constexpr double kBytesPerMeshVertex = 4096.0;

/// A generous estimate of the vertices the criteria ask for: per material, its volume over the cell
/// size cubed; its interfaces' area over the facet size squared; the feature lines' length over
/// their edge size (each segment's, resolveFeatureEdgeSizes). Volumes and areas come from sampling the oracle on a grid (24 cells along each axis),
/// so the estimate is rough (within a small factor), which is enough to tell a mesh that fits in
/// memory from one of 10^12 vertices. Criteria that are unset count as 1/20 of the diagonal.
double estimateMeshVertices(const HierarchicalOracle& oracle, const MaterialCriteria& criteria,
  const FeatureSegments& features);

/// The same estimate in its three parts, for messages that say which criterion asks for the most.
struct MeshSizeEstimate
{
  double volume = 0.0;   ///< the materials' volumes at their cell sizes
  double surfaces = 0.0; ///< the interfaces' areas at their facet sizes
  double lines = 0.0;    ///< the feature lines' lengths at their edge sizes
  double total() const { return volume + surfaces + lines; }
};
MeshSizeEstimate estimateMeshSize(const HierarchicalOracle& oracle, const MaterialCriteria& criteria,
  const FeatureSegments& features);

/// Criteria asking for more than this times the vertex budget are refused (checkMeshSize): the
/// estimate is rough (it does not see curvature; docs/journal/2026-12-02-slips.md), so a run that
/// ends a little above its budget still runs, and stops there with a warning.
constexpr double kBudgetRefusalFactor = 10.0;
/// A rate no run reaches, seconds per vertex of the whole call (several times faster than the
/// fastest measured): a run whose estimate at this rate exceeds its time limit cannot finish
/// within it.
constexpr double kFastestSecondsPerVertex = 1e-5;

/// Refuses (InputError), before any meshing, criteria that the run cannot meet: an estimate of more
/// than kBudgetRefusalFactor x `budget` vertices (0 = no budget), or more vertices than `timeLimit`
/// seconds (0 = none) allow at kFastestSecondsPerVertex. The message gives the numbers, the part that
/// asks the most, and the fixes (the criteria to coarsen, by how much; the budget or limit to raise).
void checkMeshSize(const MeshSizeEstimate& estimate, double budget, double timeLimit);

/// A size criterion of one material cannot be what was meant when it is larger than the whole domain
/// (the diagonal of the oracle's bounds) or this many times smaller than it (metres against
/// millimetres is 1000x).
constexpr double kUnitsSlipRatio = 1000.0;

/// Warnings naming each size criterion (FacetSize, CellSize, EdgeSize; FacetDistance only when
/// larger than the domain) that is larger than the whole domain or kUnitsSlipRatio times smaller
/// than it, with both numbers: a units slip, or a typo, that would otherwise mesh silently.
std::vector<std::string> criteriaScaleWarnings(const HierarchicalOracle& oracle, const MaterialCriteria& criteria);

/// The volume part alone (each material's volume over its cell size cubed): what the mesher's
/// progress expects of refinement.
double estimateCellVertices(const HierarchicalOracle& oracle, const MaterialCriteria& criteria);
}
