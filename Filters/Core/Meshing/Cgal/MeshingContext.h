// SPDX-License-Identifier: GPL-3.0-or-later
// Private to the sequential Mesh_3 translation unit (Meshing/OracleMesher.cxx) and the tests that
// call its phases: what the phases of one meshing run share.
#pragma once

#include "FeatureNetworkSimplification.h"
#include "FeatureSegments.h"
#include "HierarchicalOracle.h"
#include "MeshCriteria.h"
#include "MeshingDeadline.h"
#include "OracleMesher.h"
#include "OracleMeshDomain.h"
#include "SegmentConformation.h"
#include "SegmentState.h"
#include "SequentialTypes.h"
#include "SliverAvoidingPoint.h"

#include <algorithm>
#include <atomic>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace omesh::cgal::sequential
{
/// The state of one meshing run that its phases hand on to each other (InitialComplex,
/// BallProtection, RefinementRounds, SliverOptimisation, CheckedOutput): the inputs, the feature
/// lines as meshed, CGAL's domain and criteria, the complex and the segment state, and the
/// warnings collected on the way. Each phase keeps its own figures and records them itself.
struct MeshingContext
{
  MeshingContext(const HierarchicalOracle& o, const FeatureSegments& givenFeatures, const MesherOptions& opts)
    : oracle(o)
    , given(givenFeatures)
    , options(opts)
    , deadline(effectiveTimeLimit(opts))
  {
  }
  MeshingContext(const MeshingContext&) = delete;
  MeshingContext& operator=(const MeshingContext&) = delete;

  /// Progress for the caller; throws MeshingAborted when it asks to stop.
  void report(double fraction, const char* phase) const
  {
    if (options.progress && !options.progress(fraction, phase))
      throw MeshingAborted();
  }

  /// A sub-segment missing from the mesh is worth splitting only where a material touches it (not
  /// on a feature line outside every domain).
  bool touchesMaterial(const Vec3& a, const Vec3& b) const { return oracle.touchesMaterial(a, b); }

  const HierarchicalOracle& oracle;
  const FeatureSegments& given;
  const MesherOptions& options;
  const Clock::time_point started = Clock::now();
  MeshingDeadline deadline; ///< asked by every phase: between steps, and inside the long ones
  /// Stops CGAL's feature protection at its next ball (StoppableEdgeSize), set when the deadline passed.
  std::atomic<bool> stopProtection{ false };
  std::vector<std::string> warnings;
  BoundingBox inner, box; ///< the materials' bounds; with room around them, the domain's
  std::optional<FeatureSegments> resampled; ///< the feature lines resampled, when the options ask it
  FeatureNetworkReport network;             ///< what the resampling did
  const FeatureSegments* features = nullptr; ///< the lines meshed: the resampled ones, else the given ones
  MeshCriteria::Values g{};                  ///< the global criteria
  std::vector<double> edgeSizes; ///< each feature segment's edge size (the per-feature level, FeatureEdgeSizes.h)
  std::unique_ptr<MeshDomain> domain;
  std::unique_ptr<Criteria> criteria;
  bool protect = false;    ///< ProtectingBalls with feature lines
  bool conforming = false; ///< Conforming with feature lines
  int threads = 1;         ///< of the refinement (MesherOptions::threads)
  double edgeSize = 0.0;   ///< of the protecting balls (0 = none asked; the finest when lines differ)
  SegmentSet conformed;    ///< rule T1's result, until the segment state owns it
  std::unique_ptr<C3t3> c3t3;
  std::unique_ptr<SegmentState<C3t3>> segments; ///< Conforming only
};

/// Whether the cell level picks its refinement points (SliverAvoidingPoint, ConformingMesher3):
/// every run but ProtectingBalls' (whose balls' weights CGAL's cells must see as they are); a
/// parallel refinement takes CGAL's circumcentres, then one thread refines the slivers it left
/// at picked points.
inline bool picksRefinementPoints(const MesherOptions& options)
{
  return options.strategy != FeatureStrategy::ProtectingBalls && effectivePickingSliverAngle(options) > 0;
}

/// Where the cell level takes its refinement points, and the angle below which any cell is
/// refined.
inline PickingRegion pickingRegionOf(const MesherOptions& options)
{
  PickingRegion r;
  r.targetAngle = options.sliverAngle;
  r.seed = options.seed;
  if (picksRefinementPoints(options))
  {
    const double angle = effectivePickingSliverAngle(options);
    r.candidates = kPickingCandidates;
    r.radius = kPickingRadius;
    r.targetAngle = std::max(r.targetAngle, angle);
  }
  return r;
}
}
