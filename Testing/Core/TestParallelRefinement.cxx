// SPDX-License-Identifier: GPL-3.0-or-later
// MesherOptions::threads > 1: CGAL's parallel refinement (ParallelRefinement.cxx). Its meshes differ
// from run to run, so these tests check what a parallel run promises: the same criteria, volumes,
// validity and feature lines as the sequential run, not the same mesh.
#include "BoxDomain.h"
#include "HierarchicalOracle.h"
#include "InputError.h"
#include "LabelMapDomain.h"
#include "MeshQuality.h"
#include "MeshValidity.h"
#include "OracleMesher.h"
#include "SphereDomain.h"
#include "SurfaceDomain.h"
#include "TestShapes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>

using namespace omesh;

namespace
{
/// A ball (material 1, coarse) over a box (material 2, finer through a per-material size).
HierarchicalOracle ballOverBox()
{
  HierarchicalOracle o;
  o.add(std::make_shared<SphereDomain>(Vec3{ 0, 0, 0 }, 1.0, 1));
  o.add(std::make_shared<BoxDomain>(Vec3{ -0.5, -0.5, -2 }, Vec3{ 0.5, 0.5, -0.5 }, 2));
  return o;
}

MesherOptions ballOverBoxOptions(int threads)
{
  MesherOptions o;
  o.strategy = FeatureStrategy::None;
  o.criteria.global = { 25.0, 0.15, 0.01, 0.15, 2.0, 0.0 }; // angle, facet size, distance, cell size, radius-edge, edge
  MeshCriteria fine = MeshCriteria::inheritAll();
  fine.cellSize = 0.08;
  o.criteria.perMaterial[2] = fine;
  o.seed = 3;
  o.threads = threads;
  return o;
}

double stat(const TetMesh& m, const std::string& name)
{
  const auto it = m.statistics.find(name);
  return it == m.statistics.end() ? -1.0 : it->second;
}

/// The warnings, one per line (a failed validity assertion shows which defect it was).
std::string warnings(const TetMesh& m)
{
  std::string all;
  for (const std::string& w : m.warnings)
    all += w + "\n";
  return all;
}

bool hasWarning(const TetMesh& m, const std::string& text)
{
  return std::any_of(m.warnings.begin(), m.warnings.end(), [&](const std::string& w) { return w.find(text) != std::string::npos; });
}

/// Every tetrahedron's circumradius within its material's cell size (what refinement guarantees).
void expectCellSizes(const TetMesh& m, const std::map<int, double>& size)
{
  for (size_t t = 0; t < m.tets.size(); ++t)
  {
    const auto& k = m.tets[t];
    const Vec3 c = circumcenter(m.points[k[0]], m.points[k[1]], m.points[k[2]], m.points[k[3]]);
    ASSERT_LE(norm(m.points[k[0]] - c), size.at(m.tetMaterial[t]) * (1 + 1e-9)) << "tet " << t;
  }
}
}

TEST(ParallelRefinement, SameCriteriaVolumesAndValidityAsSequential)
{
  const HierarchicalOracle o = ballOverBox();
  MesherOptions seqOptions = ballOverBoxOptions(1), parOptions = ballOverBoxOptions(2);
  seqOptions.perturb = seqOptions.exude = parOptions.perturb = parOptions.exude = false;
  // circumcentres in both, for the same work (picked points: SliversLeftByTheThreads...)
  seqOptions.pickingSliverAngle = parOptions.pickingSliverAngle = 0;
  const TetMesh seq = meshOracle(o, {}, {}, seqOptions);
  const TetMesh par = meshOracle(o, {}, {}, parOptions);
  EXPECT_EQ(stat(seq, "refinement_threads"), 1.0);
  EXPECT_EQ(stat(par, "refinement_threads"), 2.0);
  EXPECT_TRUE(par.warnings.empty()) << par.warnings.front();
  EXPECT_EQ(stat(par, "validity.defects"), 0.0) << warnings(par);
  expectCellSizes(par, { { 1, 0.15 }, { 2, 0.08 } });
  const auto vs = materialVolumes(seq), vp = materialVolumes(par);
  ASSERT_EQ(vp.size(), 2u);
  for (const auto& [mat, v] : vs)
    EXPECT_NEAR(vp.at(mat), v, 0.005 * v) << "material " << mat;
  // as many tetrahedra give or take a few percent (the criteria, not the order of insertions, set the density)
  EXPECT_NEAR(static_cast<double>(par.tets.size()), static_cast<double>(seq.tets.size()), 0.1 * seq.tets.size());
}

TEST(ParallelRefinement, SliversLeftByTheThreadsAreRefinedAtPickedPoints)
{
  // The threads refine at circumcentres and leave slivers; a sequential pass refines those at
  // picked points, so without any optimisation the parallel mesh reaches the picking angle as the
  // sequential one does (12 degrees at radius-edge 2).
  const HierarchicalOracle o = ballOverBox();
  MesherOptions options = ballOverBoxOptions(2);
  options.perturb = options.exude = false;
  const double angle = effectivePickingSliverAngle(options);
  ASSERT_GE(angle, 12.0);
  const TetMesh par = meshOracle(o, {}, {}, options);
  EXPECT_EQ(stat(par, "refinement_threads"), 2.0);
  EXPECT_GT(stat(par, "refinement_point_picks"), 0.0);
  EXPECT_EQ(stat(par, "validity.defects"), 0.0) << warnings(par);
  EXPECT_GE(stat(par, "min_dihedral_angle"), angle - 1e-6);
  // every sliver the threads left costs a vertex: more tetrahedra than the sequential run, not many
  MesherOptions sequential = options;
  sequential.threads = 1;
  const TetMesh seq = meshOracle(o, {}, {}, sequential);
  EXPECT_LT(static_cast<double>(par.tets.size()), 1.25 * static_cast<double>(seq.tets.size()));
  // without picking, the threads alone: the bound is the sliver angle only
  options.pickingSliverAngle = 0;
  const TetMesh plain = meshOracle(o, {}, {}, options);
  EXPECT_EQ(stat(plain, "refinement_point_picks"), -1.0);
  EXPECT_GE(stat(plain, "min_dihedral_angle"), options.sliverAngle);
}

TEST(ParallelRefinement, OptimisedMeshKeepsItsAngleBounds)
{
  // The optimisers run on the copied-back complex as after a sequential refinement. A parallel
  // mesh differs from run to run, so only what holds for every run is asserted: the refinement's
  // sliver rule (no cell below SliverAngle), optimisers that never lower the smallest angle, and no
  // sliver left (the sequential run ends near 12 degrees; parallel runs were seen at 9.6-12).
  const HierarchicalOracle o = ballOverBox();
  const MesherOptions options = ballOverBoxOptions(2);
  const TetMesh par = meshOracle(o, {}, {}, options);
  EXPECT_EQ(stat(par, "validity.defects"), 0.0) << warnings(par);
  EXPECT_GE(stat(par, "optimisation.min_dihedral_before"), options.sliverAngle);
  EXPECT_GE(stat(par, "min_dihedral_angle"), stat(par, "optimisation.min_dihedral_before"));
  EXPECT_GE(stat(par, "min_dihedral_angle"), 5.0);
}

TEST(ParallelRefinement, LabelMapVolumesAsSequential)
{
  const std::array<int, 3> d{ 24, 24, 24 };
  std::vector<int> labels(static_cast<size_t>(d[0]) * d[1] * d[2], 0);
  for (int k = 0; k < d[2]; ++k)
    for (int j = 0; j < d[1]; ++j)
      for (int i = 0; i < d[0]; ++i)
      {
        const double r = norm(Vec3{ i + 0.5, j + 0.5, k + 0.5 } - Vec3{ 12, 12, 12 });
        labels[i + d[0] * (j + d[1] * k)] = r < 4 ? 2 : (r < 8 ? 1 : 0);
      }
  HierarchicalOracle o;
  o.add(std::make_shared<LabelMapDomain>(d, labels,
    LabelMapDomain::cellCenteredWorldToVoxel({ 0, 0, 0 }, { 1, 1, 1 }, { 1, 0, 0, 0, 1, 0, 0, 0, 1 }), 0, "balls",
    LabelInterpolation::Trilinear));
  MesherOptions opt;
  opt.strategy = FeatureStrategy::None;
  opt.criteria.global = { 25.0, 1.0, 0.08, 1.0, 3.0, 0.0 };
  opt.perturb = opt.exude = false;
  const TetMesh seq = meshOracle(o, {}, {}, opt);
  opt.threads = 2;
  const TetMesh par = meshOracle(o, {}, {}, opt);
  EXPECT_EQ(stat(par, "validity.defects"), 0.0) << warnings(par);
  expectCellSizes(par, { { 1, 1.0 }, { 2, 1.0 } });
  const auto vs = materialVolumes(seq), vp = materialVolumes(par);
  ASSERT_EQ(vp.size(), 2u);
  for (const auto& [mat, v] : vs)
    EXPECT_NEAR(vp.at(mat), v, 0.01 * v) << "material " << mat;
}

TEST(ParallelRefinement, ProtectingBallsKeepTheCubeEdges)
{
  HierarchicalOracle o;
  o.add(std::make_shared<SurfaceDomain>(test::cube(0, 1), 1));
  const FeatureSegments edges = test::cubeEdges(0, 1);
  MesherOptions opt;
  opt.strategy = FeatureStrategy::ProtectingBalls;
  opt.criteria.global = { 25.0, 0.2, 0.01, 0.2, 3.0, 0.0 };
  opt.seed = 7;
  opt.threads = 2;
  const TetMesh m = meshOracle(o, edges, {}, opt);
  EXPECT_EQ(stat(m, "refinement_threads"), 2.0);
  EXPECT_NEAR(featureCoverage(m.segments, edges), 1.0, 1e-12);
  EXPECT_NEAR(materialVolumes(m).at(1), 1.0, 0.01);
  EXPECT_EQ(stat(m, "validity.defects"), 0.0) << warnings(m);
  EXPECT_GT(stat(m, "min_dihedral_angle"), 5.0);
}

// Conforming with feature lines on 2 threads (OracleMesher's refineConformingInParallel): the
// segment level alone, CGAL's parallel levels above a read-only guard of the sub-segments'
// diametral balls, then the sequential round where the guard left elements bad. An L-shaped CAD
// part (a reentrant edge) with its sharp edges, an inner ball of a second material; edges coarser
// than the facets, so refinement points fall into the balls and the guard and the sequential
// round have work.
TEST(ParallelRefinement, ConformingKeepsTheFeatureLinesAndTheSequentialGuarantees)
{
  const TriangleSurface part = test::lPrism(1.0, { 0, 0, 0 });
  const FeatureSegments edges = test::sharpEdges(part, 60.0);
  ASSERT_EQ(edges.segments.size(), 18u); // 90-degree edges and the reentrant 270-degree one
  HierarchicalOracle o;
  o.add(std::make_shared<SphereDomain>(Vec3{ 0.5, 0.5, 0.5 }, 0.35, 2));
  o.add(std::make_shared<SurfaceDomain>(part, 1));
  MesherOptions opt;
  opt.strategy = FeatureStrategy::Conforming;
  opt.criteria.global = { 25.0, 0.25, 0.02, 0.25, 3.0, 1.0 }; // angle, facet size, distance, cell size, radius-edge, edge
  opt.seed = 7;
  const TetMesh seq = meshOracle(o, edges, {}, opt);
  opt.threads = 2;
  const TetMesh par = meshOracle(o, edges, {}, opt);
  EXPECT_EQ(stat(par, "refinement_threads"), 2.0);
  // nothing to warn about but, in some thread schedules (about 1 run in 10 under the sanitizers),
  // an exudation undone because it would have lowered the smallest angle (asserted below)
  for (const std::string& w : par.warnings)
    EXPECT_EQ(w.rfind("exudation undone: it would have lowered", 0), 0u) << warnings(par);
  // the guard refused points (hundreds in every run seen) and the sequential round took them
  EXPECT_GT(stat(par, "parallel_conforming.elements_left_to_sequential_tail"), 0.0);
  EXPECT_EQ(stat(par, "parallel_conforming.sequential_tail_ran"), 1.0);
  EXPECT_GT(stat(par, "parallel_conforming.vertices_after_parallel"), stat(par, "parallel_conforming.vertices_after_segments"));
  // every constrained segment is present as mesh edges, no defect, the refinement reaches the
  // picking angle (the sequential round refines the slivers the threads left) and the optimisers
  // never lower the smallest angle, as in the sequential run
  EXPECT_NEAR(featureCoverage(par.segments, edges), 1.0, 1e-12);
  EXPECT_EQ(stat(par, "segment_pieces_missing_unfinished"), 0.0);
  EXPECT_EQ(stat(par, "validity.defects"), 0.0) << warnings(par);
  EXPECT_GE(stat(par, "optimisation.min_dihedral_before"), effectivePickingSliverAngle(opt) - 1e-6);
  EXPECT_GE(stat(seq, "optimisation.min_dihedral_before"), effectivePickingSliverAngle(opt) - 1e-6);
  EXPECT_GE(stat(par, "min_dihedral_angle"), stat(par, "optimisation.min_dihedral_before"));
  EXPECT_GE(stat(par, "min_dihedral_angle"), 5.0);
  // the volumes of both runs, within the accuracy of meshes this coarse (the ball's facets are
  // chords within the facet distance d of it: at most 3 d / r of its volume), and of each other
  const auto vs = materialVolumes(seq), vp = materialVolumes(par);
  ASSERT_EQ(vp.size(), 2u);
  const double ball = 4.0 / 3.0 * M_PI * std::pow(0.35, 3);
  for (const auto& v : { vs, vp })
  {
    EXPECT_NEAR(v.at(1) + v.at(2), 4.0, 0.002 * 4.0); // the L prism: 3 x 1 x 1 + 1 x 1 x 1
    EXPECT_NEAR(v.at(2), ball, 3 * 0.02 / 0.35 * ball);
  }
  for (const auto& [mat, v] : vs)
    EXPECT_NEAR(vp.at(mat), v, 0.02 * v) << "material " << mat << ": " << vp.at(mat) << " / " << v;
}

TEST(ParallelRefinement, AbortVertexBudgetAndBadThreads)
{
  HierarchicalOracle o;
  o.add(std::make_shared<SphereDomain>(Vec3{ 0, 0, 0 }, 1.0, 1));
  MesherOptions abort = ballOverBoxOptions(2);
  abort.criteria.global.cellSize = abort.criteria.global.facetSize = 0.02;
  int calls = 0;
  abort.progress = [&](double, const char* phase) { return std::string(phase) != "refinement" || ++calls < 3; };
  EXPECT_THROW(meshOracle(o, {}, {}, abort), MeshingAborted);

  // A parallel run that reaches the vertex budget is meshed again on one thread (a parallel run
  // stopped early leaves deep clusters): the mesh is the sequential run's, with a warning.
  MesherOptions budget = ballOverBoxOptions(2);
  budget.criteria.global.cellSize = budget.criteria.global.facetSize = 0.02;
  budget.maximumNumberOfVertices = 3000;
  budget.perturb = budget.exude = false;
  const TetMesh m = meshOracle(o, {}, {}, budget);
  EXPECT_TRUE(hasWarning(m, "MaximumNumberOfVertices = 3000: the criteria")) << warnings(m);
  EXPECT_TRUE(hasWarning(m, "refined again on one thread")) << warnings(m);
  EXPECT_GT(stat(m, "parallel.budget_retry_seconds"), 0.0);
  EXPECT_EQ(stat(m, "refinement_threads"), 1.0);
  EXPECT_EQ(stat(m, "validity.defects"), 0.0) << warnings(m);
  MesherOptions sequential = budget;
  sequential.threads = 1;
  const TetMesh seq = meshOracle(o, {}, {}, sequential);
  ASSERT_EQ(m.points.size(), seq.points.size());
  for (size_t i = 0; i < m.points.size(); ++i)
    ASSERT_TRUE(m.points[i].x == seq.points[i].x && m.points[i].y == seq.points[i].y && m.points[i].z == seq.points[i].z) << i;
  EXPECT_EQ(m.tets, seq.tets);

  MesherOptions bad = ballOverBoxOptions(-1);
  try
  {
    meshOracle(o, {}, {}, bad);
    ADD_FAILURE() << "threads = -1 accepted";
  }
  catch (const InputError& e)
  {
    EXPECT_NE(std::string(e.what()).find("Threads = -1"), std::string::npos) << e.what();
  }
}

// The time limit (MeshingDeadline) stops a parallel refinement too: asked where the progress and
// the vertex budget are, every 50 ms. Refinement to a tiny size with no vertex budget would run for
// minutes; the limit ends it in the refinement phase, with the vertices seen so far.
TEST(ParallelRefinement, TimeLimitStopsTheRefinement)
{
  HierarchicalOracle o;
  o.add(std::make_shared<SphereDomain>(Vec3{ 0, 0, 0 }, 1.0, 1));
  MesherOptions opt = ballOverBoxOptions(2);
  opt.criteria.global.cellSize = opt.criteria.global.facetSize = 0.002;
  opt.maximumNumberOfVertices = 0;
  // 1 s, then (on a machine so loaded, or a build so slow, that refinement had barely begun) 4 s
  for (double limit : { 1.0, 4.0 })
  {
    SCOPED_TRACE(limit);
    opt.timeLimit = limit;
    const auto started = std::chrono::steady_clock::now();
    try
    {
      meshOracle(o, {}, {}, opt);
      ADD_FAILURE() << "meshed within the limit: no longer a case for the time limit";
      return;
    }
    catch (const TimeLimitReached& e)
    {
      EXPECT_EQ(e.phase, "refinement") << e.what();
      EXPECT_GE(e.statistics.at("time.elapsed"), limit);
      EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count(), 30.0 * limit);
      // the parallel complex's vertices, not the initial points
      if (e.statistics.at("vertices") > 100.0)
        return;
      if (limit > 1.0)
        ADD_FAILURE() << e.what();
    }
  }
}

// Under criteria no facet can meet, threads refined facets that another thread's insertion had
// just made stale: their points landed ulps from fresh vertices, and 2-thread runs wrote hundreds
// of duplicate vertices with flat tets around them (reported as defects), or failed with CGAL's
// "already inserted". The guard (ParallelGuardLevel) refuses such points; the runs then ended at
// the vertex budget with thousands of flat tets in deep clusters (the parallel levels refine
// depth-first), so a parallel run at the budget is meshed again on one thread. Every run ends
// valid. Parallel runs differ: three of each.
TEST(ParallelRefinement, CriteriaNoFacetCanMeetStayValid)
{
  HierarchicalOracle o;
  o.add(std::make_shared<SphereDomain>(Vec3{ 0, 0, 0 }, 3.0, 2));
  o.add(std::make_shared<BoxDomain>(Vec3{ -5, -5, -5 }, Vec3{ 5, 5, 5 }, 1));
  for (const char* impossible : { "facet angle 89", "facet size 1e-9" })
    for (int run = 0; run < 3; ++run)
    {
      MesherOptions opt;
      opt.strategy = FeatureStrategy::None;
      opt.criteria.global = { 25.0, 2.0, 0.5, 2.0, 3.0, 0.0 }; // angle, facet size, distance, cell size, radius-edge, edge
      if (std::string(impossible) == "facet angle 89")
        opt.criteria.global.facetAngle = 89;
      else
        opt.criteria.global.facetSize = 1e-9;
      opt.seed = 1;
      opt.threads = 2;
      opt.maximumNumberOfVertices = 3000;
      // the exuder spends minutes on such a mesh (OracleMesherTimeLimit); refinement is what is tested
      opt.perturb = opt.exude = opt.improveAngles = false;
      opt.timeLimit = 60;
      SCOPED_TRACE(std::string(impossible) + ", run " + std::to_string(run));
      const TetMesh m = meshOracle(o, {}, {}, opt);
      EXPECT_TRUE(hasWarning(m, "MaximumNumberOfVertices")) << warnings(m);
      EXPECT_TRUE(hasWarning(m, "refined again on one thread")) << warnings(m);
      EXPECT_EQ(stat(m, "validity.defects"), 0.0) << warnings(m);
      // checked again here, the oracle's materials too
      const MeshValidity v = checkMeshValidity(m, [&](const Vec3& p) { return o.material(p); });
      EXPECT_TRUE(v.valid()) << v.describe();
    }
}
