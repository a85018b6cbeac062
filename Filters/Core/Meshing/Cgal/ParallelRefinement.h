// SPDX-License-Identifier: GPL-3.0-or-later
// Private to the mesher (includes CGAL): CGAL's parallel Mesh_3 refinement (Parallel_tag, TBB) for
// the mesher's sequential complex, in a translation unit of its own (ParallelRefinement.cxx): the
// second triangulation type doubles CGAL's template instantiations, and this way the sequential
// mesher's translation unit stays as it is and both compile side by side.
#pragma once

#include "MeshTriangulation3.h"
#include "OracleMesher.h"
#include "SegmentConformation.h"

#include <cstddef>
#include <functional>
#include <vector>

namespace omesh::cgal
{
using SequentialC3t3 = MeshTriangulation3<CGAL::Sequential_tag>::C3t3;

/// How a parallel refinement ended.
struct ParallelRefinementRun
{
  bool budgetHit = false;  ///< stopped at MesherOptions::maximumNumberOfVertices
  bool stalled = false;    ///< stopped after 5 minutes without a new vertex (see refineInParallel)
  double cpuSeconds = 0.0; ///< CPU seconds of the threads other than the calling one, during the call
  /// CPU seconds of the busiest refinement thread: with the calling thread's (the copies), what
  /// the refinement takes on idle cores (a shared machine's load hides it from the wall time)
  double busiestThreadCpu = 0.0;
  /// The refinement points of the elements the guard left bad (ParallelGuardLevel)
  std::vector<Vec3> leftBad;
  /// How many of them repeated a vertex (a stale element's point)
  std::size_t repeatsRefused = 0;
};

/// The number of threads MesherOptions::threads asks for (0 = every core of the machine).
int requestedThreads(const MesherOptions& options);

/// Refines the initialised `c3t3` as CGAL's Mesher_3 does (the domain, the mesher's criteria of
/// `options` with `edgeSize` for the protecting balls), on `threads` threads with CGAL's
/// Parallel_tag: the complex is copied into a concurrent triangulation, refined and copied back
/// (vertices, cells, their Mesh_3 data, corners, feature edges, far points).
/// `progress` is called from the calling thread about every 50 ms with the (approximate) number of
/// vertices; when it throws, the refinement is stopped and the exception passed on.
/// Not deterministic: the order of insertions depends on the threads' timing. A point that repeats
/// a vertex is not inserted (ParallelGuardLevel); its element is left bad. A run whose vertex
/// count stays the same for 5 minutes is stopped (`stalled`). After a stop (budget, stall) the cells may not all be in the complex yet: the
/// caller scans them (Mesher_3::fix_c3t3), as after a sequential stop.
/// `protectedSegments` (Conforming; null for the other strategies): sub-segments, each a vertex
/// pair of `c3t3` with an empty diametral ball, into whose balls nothing is inserted
/// (ParallelGuardLevel: the facets and cells whose points fall there are left as they are, for the
/// sequential refinement that follows).
ParallelRefinementRun refineInParallel(SequentialC3t3& c3t3, const MeshDomain& domain, const MesherOptions& options,
  double edgeSize, int threads, const std::function<void(std::size_t)>& progress,
  const SegmentSet* protectedSegments = nullptr);
}
