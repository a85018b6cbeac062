// SPDX-License-Identifier: GPL-3.0-or-later
// Private to the sequential Mesh_3 translation unit (Meshing/OracleMesher.cxx) and the tests that
// call its phases: the meshing run's inputs and its initial complex.
#pragma once

#include "BallProtection.h"
#include "FeatureEdgeSizes.h"
#include "FeatureLineResampling.h"
#include "MaterialCriteria3.h"
#include "MeshingContext.h"

#include <CGAL/make_mesh_3.h>

#include <cmath>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace omesh::cgal::sequential
{
/// The phases before refinement: the feature lines resampled (when asked) and checked with the
/// criteria; the oracle as CGAL's mesh domain with our criteria; rule T1 on the segments alone
/// (Conforming) or the protecting balls (ProtectingBalls, BallProtection); then the initial
/// complex: far points, CGAL's initial points, the caller's seed points and the conformed segment
/// points.
///
/// @sa RefinementRounds (the phase after it)
class InitialComplex
{
public:
  explicit InitialComplex(MeshingContext& run)
    : run_(run)
  {
  }

  /// Every step, in order.
  void run(const std::vector<Vec3>& seedPoints)
  {
    prepareInputs();
    buildDomainAndCriteria();
    conformSegmentsT1();
    initialPoints(seedPoints);
  }

  /// Resampled feature lines (if asked), criteria and feature lines checked.
  void prepareInputs()
  {
    run_.inner = run_.oracle.bounds(); // throws for an empty or unbounded oracle
    run_.given.checkEdgeSizes();   // named on the lines as given, before resampling moves them
    if (const auto dense = denseFeatureLinesWarning(run_.given, run_.options, run_.inner))
      run_.warnings.push_back(*dense);
    run_.resampled = resampledFeatures(run_.given, run_.options, run_.oracle, run_.inner, run_.warnings, run_.network);
    run_.features = run_.resampled ? &*run_.resampled : &run_.given;
    run_.deadline.check("feature-line resampling");
    checkCriteria(run_.options.criteria, run_.warnings);
    run_.g = run_.options.criteria.globalValues();
    if (!run_.features->empty())
    {
      auto w = run_.features->validate(run_.oracle, run_.g.cellRadiusEdgeRatio);
      run_.warnings.insert(run_.warnings.end(), w.begin(), w.end());
      run_.deadline.check("feature-line validation");
    }
    run_.edgeSizes = resolveFeatureEdgeSizes(*run_.features, run_.options.criteria, run_.oracle);
    run_.report(0.0, "initialisation");
  }

  /// The oracle as CGAL's mesh domain (with the polylines to protect for ProtectingBalls) and the
  /// criteria: ours per material; CGAL's topology criterion (facet vertices on the surface, T2).
  void buildDomainAndCriteria()
  {
    // A little room around the materials, so the boundary never touches the domain's box.
    run_.box = run_.inner;
    const Vec3 pad = 0.02 * run_.box.size() + (1e-9 * (1.0 + norm(run_.box.size()))) * Vec3{ 1, 1, 1 };
    run_.box.add(run_.box.min - pad);
    run_.box.add(run_.box.max + pad);
    run_.domain = std::make_unique<MeshDomain>(run_.oracle, run_.box, run_.options.seed);
    run_.protect = run_.options.strategy == FeatureStrategy::ProtectingBalls && !run_.features->empty();
    StoppableEdgeSize sizing{ 1.0, &run_.stopProtection };
    run_.edgeSize = run_.g.edgeSize;
    if (run_.protect)
      sizing = BallProtection(run_).sizing();
    else
      sizing.size = run_.edgeSize > 0 ? run_.edgeSize : 1.0;
    // before the criteria (the parallel levels take circumcentres at SliverAngle; the sequential
    // round after them picks its points around the slivers they left)
    run_.threads = requestedThreads(run_.options);
    run_.criteria = std::make_unique<Criteria>(
      materialMeshCriteria<Tr>(run_.options, Criteria::Edge_criteria(sizing), pickingRegionOf(run_.options).targetAngle, &run_.oracle));
  }

  /// Conforming: rule T1 on the segments alone first (SegmentConformation.h); the domain's
  /// initial points keep away from their points (a near-coincident pair seeds a cluster of micro
  /// tetrahedra).
  void conformSegmentsT1()
  {
    run_.conforming = run_.options.strategy == FeatureStrategy::Conforming && !run_.features->empty();
    if (!run_.conforming)
      return;
    const size_t budget = run_.options.maximumNumberOfVertices ? run_.options.maximumNumberOfVertices : 1000000;
    run_.conformed =
      conformSegments(*run_.features, run_.edgeSizes, budget, run_.warnings, [this] { run_.deadline.tick("feature-line conformation"); });
    run_.domain->avoidInitialPointsNear(run_.conformed.points);
  }

  /// The initial point set: far points, then CGAL's initial points (or its protecting balls), the
  /// caller's seed points, and (Conforming) the conformed segment points.
  void initialPoints(const std::vector<Vec3>& seedPoints)
  {
    CGAL::get_default_random() = CGAL::Random(run_.options.seed);
    run_.c3t3 = std::make_unique<C3t3>();
    const auto initStart = Clock::now();
    addFarPoints();
    if (run_.protect)
    {
      BallProtection balls(run_);
      balls.initialPointsAwayFromFeatures();
      balls.protect();
    }
    else
      CGAL::Mesh_3::internal::init_c3t3(*run_.c3t3, *run_.domain, *run_.criteria, 20);
    insertSeedPoints(seedPoints);
    initTime_ = seconds(initStart);
    insertSegmentPoints();
  }

  /// Far points around the domain keep the triangulation's hull away from the material boundary:
  /// a circumcentre on a convex domain's boundary would otherwise land on the hull (CGAL adds such
  /// points itself only in parallel mode, and not after feature protection).
  void addFarPoints()
  {
    const Vec3 c = 0.5 * (run_.box.min + run_.box.max);
    const double r = 2.0 * norm(run_.box.size());
    for (int i = 0; i < 8; ++i)
    {
      const Vec3 dir{ (i & 1) ? 1.0 : -1.0, (i & 2) ? 1.0 : -1.0, (i & 4) ? 1.0 : -1.0 };
      run_.c3t3->add_far_point(Tr::Point(toPoint(c + (r / std::sqrt(3.0)) * dir)));
    }
  }

  /// The paper's a-priori points, in the material the oracle gives them.
  void insertSeedPoints(const std::vector<Vec3>& seedPoints)
  {
    for (const Vec3& p : seedPoints)
    {
      const int m = run_.oracle.material(p);
      if (m == kOutside)
      {
        run_.warnings.push_back("seed point outside every material ignored");
        continue;
      }
      Tr::Vertex_handle v = run_.c3t3->triangulation().insert(Tr::Point(toPoint(p)));
      if (v != Tr::Vertex_handle())
      {
        run_.c3t3->set_dimension(v, 3);
        run_.c3t3->set_index(v, run_.domain->index_from_subdomain_index(subdomainOf(m)));
      }
    }
  }

  /// Conforming: the segments, conformed by rule T1, enter the triangulation; their points are
  /// mesh vertices of dimension 0 (input points) or 1 (on a segment), which CGAL's perturber never
  /// moves. Refinement then keeps every sub-segment's diametral ball empty (T1.2) and refuses
  /// refinement points inside them (T2.1, T3.1): see SegmentRefinementLevel.
  void insertSegmentPoints()
  {
    if (!run_.conforming)
      return;
    run_.segments = std::make_unique<SegmentState<C3t3>>(*run_.c3t3, std::move(run_.conformed));
    // collinear points: an insertion can take milliseconds
    run_.segments->insertPoints(*run_.domain, [this] { run_.deadline.check("inserting the feature-line points"); });
    run_.c3t3->rescan_after_load_of_triangulation();
  }

  /// Its statistics.
  void record(std::map<std::string, double>& st) const { st["time.initialisation"] = initTime_; }

private:
  MeshingContext& run_;
  double initTime_ = 0.0;
};
}
