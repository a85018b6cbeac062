// SPDX-License-Identifier: GPL-3.0-or-later
// The mesher's phases called one by one (Meshing/Cgal/MeshingRun.h): in order they give
// meshOracle's mesh; alone they reach the paths real inputs take rarely (the exuder undone, the
// segment repair after perturbation).
#include "HierarchicalOracle.h"
#include "MeshQuality.h"
#include "MeshingRun.h"
#include "OracleMesher.h"
#include "ShapeSummary.h"
#include "SurfaceDomain.h"
#include "TestShapes.h"
#include "WorkerThreads.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace
{
using namespace omesh;
using omesh::cgal::sequential::MeshingRun;
using omesh::cgal::sequential::Tr;

MesherOptions cubeOptions(double cellSize)
{
  MesherOptions o;
  o.strategy = FeatureStrategy::Conforming;
  o.criteria.global.cellSize = cellSize;
  o.criteria.global.facetSize = cellSize;
  o.criteria.global.facetDistance = cellSize / 20;
  o.criteria.global.cellRadiusEdgeRatio = 3;
  o.seed = 7;
  return o;
}

HierarchicalOracle unitCube()
{
  HierarchicalOracle o;
  o.add(std::make_shared<SurfaceDomain>(test::cube(0, 1), 1));
  return o;
}

bool hasWarning(const TetMesh& m, const std::string& text)
{
  return std::any_of(m.warnings.begin(), m.warnings.end(), [&](const std::string& w) { return w.find(text) != std::string::npos; });
}

/// Each tetrahedron as its sorted corner coordinates and its material: the same mesh compares equal
/// whatever the numbering of its points and tetrahedra.
std::vector<std::pair<std::array<std::array<double, 3>, 4>, int>> tetSet(const TetMesh& m)
{
  std::vector<std::pair<std::array<std::array<double, 3>, 4>, int>> out;
  for (size_t t = 0; t < m.tets.size(); ++t)
  {
    std::array<std::array<double, 3>, 4> corners;
    for (int k = 0; k < 4; ++k)
    {
      const Vec3& p = m.points[m.tets[t][k]];
      corners[k] = { p.x, p.y, p.z };
    }
    std::sort(corners.begin(), corners.end());
    out.push_back({ corners, m.tetMaterial[t] });
  }
  std::sort(out.begin(), out.end());
  return out;
}
}

TEST(MeshingPhases, OneByOneTheyGiveMeshOraclesMesh)
{
  const HierarchicalOracle o = unitCube();
  const FeatureSegments edges = test::cubeEdges(0, 1);
  const MesherOptions opt = cubeOptions(0.25);
  const TetMesh whole = meshOracle(o, edges, {}, opt);
  MeshingRun run(o, edges, opt);
  run.initial.run({});
  ASSERT_TRUE(run.context.conforming);
  ASSERT_GT(run.context.c3t3->triangulation().number_of_vertices(), 8u) << "the segment points are in";
  run.refinement.refineAllLevels();
  const size_t refined = run.context.c3t3->number_of_cells_in_complex();
  run.optimisation.run();
  const TetMesh phased = run.finish();
  EXPECT_GT(refined, 0u);
  EXPECT_TRUE(tetSet(phased) == tetSet(whole));
  for (const char* key : { "time.initialisation", "refinement_steps", "optimisation.exudation_steps", "tetrahedra",
         "validity.defects" })
    EXPECT_EQ(phased.statistics.count(key), 1u) << key << ": each phase records its statistics";
  EXPECT_EQ(phased.statistics.at("refinement_steps"), whole.statistics.at("refinement_steps"));
}

TEST(MeshingPhases, UndoneExudationGivesBackTheMeshFromBeforeIt)
{
  // The undo rebuilds the complex from a compact record (ComplexSnapshot.h); real inputs rarely
  // need it, so it is called here and compared with a run that stops before the exuder.
  const HierarchicalOracle o = unitCube();
  const FeatureSegments edges = test::cubeEdges(0, 1);
  MesherOptions noExuder = cubeOptions(0.2);
  noExuder.exude = false;
  noExuder.improveAngles = false; // the comparison is with the complex before the exuder
  const TetMesh before = meshOracle(o, edges, {}, noExuder);
  MesherOptions pumped = noExuder;
  pumped.exudationSliverBound = 0; // pump every cell: the exuder changes the mesh
  MeshingRun run(o, edges, pumped);
  run.initial.run({});
  run.refinement.refineAllLevels();
  run.optimisation.start();
  run.optimisation.perturbKeepingSegments();
  auto exudation = run.optimisation.exude();
  ASSERT_TRUE(exudation.before.has_value());
  run.optimisation.undo(exudation, "asked by the test");
  run.optimisation.finish();
  const TetMesh undone = run.finish();
  EXPECT_GT(undone.statistics.at("optimisation.exudation_steps"), 0.0);
  EXPECT_TRUE(hasWarning(undone, "exudation undone: asked by the test"));
  EXPECT_FALSE(hasWarning(undone, "incomplete"));
  EXPECT_EQ(undone.tets.size(), before.tets.size());
  EXPECT_TRUE(tetSet(undone) == tetSet(before)) << "the undo changed the mesh from before the exuder";
  EXPECT_EQ(undone.interfaceTriangles.size(), before.interfaceTriangles.size());
  EXPECT_NEAR(featureCoverage(undone.segments, edges), 1.0, 1e-12);
  EXPECT_EQ(undone.statistics.at("validity.defects"), 0.0);
  size_t corners = 0;
  for (int d : undone.pointDimension)
    corners += d == 0;
  EXPECT_EQ(corners, 8u) << "the vertices' dimensions came back";

  // and the exuder itself changed the mesh: the undo had something to undo
  MeshingRun kept(o, edges, pumped);
  kept.initial.run({});
  kept.refinement.refineAllLevels();
  kept.optimisation.start();
  kept.optimisation.perturbKeepingSegments();
  kept.optimisation.exude();
  kept.optimisation.finish();
  EXPECT_FALSE(tetSet(kept.finish()) == tetSet(before)) << "the exuder changed nothing: nothing to undo";
}

TEST(MeshingPhases, SegmentRepairAfterPerturbationRefinesOnlyAroundTheBrokenSubSegments)
{
  // The perturber leaves cells above a tight radius-edge bound (it improves angles, not radii); a
  // run without a repair keeps them. A repair round (called here around one sub-segment, as if
  // the perturber had broken it) that scanned every element would refine all of them too.
  const HierarchicalOracle o = unitCube();
  const FeatureSegments edges = test::cubeEdges(0, 1);
  MesherOptions tight = cubeOptions(0.15);
  tight.criteria.global.cellRadiusEdgeRatio = 1.1;
  tight.exude = false;
  const TetMesh perturbed = meshOracle(o, edges, {}, tight);
  ASSERT_EQ(perturbed.statistics.at("refinement_rounds"), 1.0) << "a real repair: the comparison needs none";
  MeshingRun run(o, edges, tight);
  run.initial.run({});
  run.refinement.refineAllLevels();
  run.optimisation.start();
  run.optimisation.perturbKeepingSegments();
  const auto& segments = *run.context.segments;
  ASSERT_GT(segments.size(), 0u);
  run.refinement.repairAround({ segments.vertexOf(segments.end(0, 0)), segments.vertexOf(segments.end(0, 1)) });
  run.optimisation.finish();
  const TetMesh repaired = run.finish();
  EXPECT_EQ(repaired.statistics.at("refinement_rounds"), 2.0);
  EXPECT_EQ(repaired.statistics.at("validity.defects"), 0.0);
  EXPECT_NEAR(featureCoverage(repaired.segments, edges), 1.0, 1e-12);
  EXPECT_LE(static_cast<double>(repaired.tets.size()), 1.01 * static_cast<double>(perturbed.tets.size()))
    << perturbed.tets.size() << " tetrahedra after perturbation, " << repaired.tets.size() << " after the repair";
}

TEST(MeshingPhases, TheOutputIsTheComplexInSpaceOrder)
{
  const HierarchicalOracle o = unitCube();
  const FeatureSegments edges = test::cubeEdges(0, 1);
  const MesherOptions opt = cubeOptions(0.1); // the run keeps a reference: not a temporary
  MeshingRun run(o, edges, opt);
  run.initial.run({});
  run.refinement.refineAllLevels();
  // the complex's cells, as tetSet takes them
  TetMesh complex;
  const auto& c3t3 = *run.context.c3t3;
  std::map<Tr::Vertex_handle, int> index;
  for (auto c = c3t3.cells_in_complex_begin(); c != c3t3.cells_in_complex_end(); ++c)
  {
    std::array<int, 4> k;
    for (int i = 0; i < 4; ++i)
    {
      const auto [at, added] = index.emplace(c->vertex(i), static_cast<int>(complex.points.size()));
      if (added)
        complex.points.push_back(cgal::toVec(c->vertex(i)->point().point()));
      k[i] = at->second;
    }
    complex.tets.push_back(k);
    complex.tetMaterial.push_back(cgal::materialOf(c3t3.subdomain_index(c)));
  }
  const TetMesh mesh = run.output.convert();
  ASSERT_GT(mesh.tets.size(), 1000u);
  EXPECT_TRUE(tetSet(mesh) == tetSet(complex)) << "the same tetrahedra and materials";
  EXPECT_EQ(mesh.points.size(), complex.points.size()) << "every point used, none twice";
  EXPECT_EQ(c3t3.triangulation().number_of_vertices(), 0u) << "the complex is released";
  auto smallest = [&](size_t t) { return *std::min_element(mesh.tets[t].begin(), mesh.tets[t].end()); };
  for (size_t t = 1; t < mesh.tets.size(); ++t)
    ASSERT_LE(smallest(t - 1), smallest(t)) << "tetrahedra in the order of their smallest point, at " << t;
  // points along a space-filling curve: consecutive ones are near, much nearer than in the
  // complex's own order
  auto meanStep = [](const std::vector<Vec3>& p) {
    double sum = 0.0;
    for (size_t k = 1; k < p.size(); ++k)
      sum += norm(p[k] - p[k - 1]);
    return sum / static_cast<double>(p.size() - 1);
  };
  EXPECT_LT(meanStep(mesh.points), 0.5 * meanStep(complex.points));
  EXPECT_LT(meanStep(mesh.points), 0.2) << "about an edge length (cell size 0.1)";
}

TEST(MeshingPhases, BadCellsAreExactlyTheCellsTheCriteriaRefuseOnAnyThreadCount)
{
  // After a parallel refinement the sequential round starts from badCellsOf (judged in chunks on
  // the call's threads): judged here with criteria stricter than the run's, so that some are bad.
  const HierarchicalOracle o = unitCube();
  const FeatureSegments edges = test::cubeEdges(0, 1);
  const MesherOptions opt = cubeOptions(0.055);
  MeshingRun run(o, edges, opt);
  run.initial.run({});
  run.refinement.refineAllLevels();
  const auto& c3t3 = *run.context.c3t3;
  ASSERT_GT(c3t3.number_of_cells_in_complex(), 2 * kTetsPerChunk) << "several chunks";
  MesherOptions strict = opt;
  strict.criteria.global.cellSize = 0.035;
  const cgal::sequential::Criteria criteria =
    cgal::materialMeshCriteria<Tr>(strict, cgal::sequential::Criteria::Edge_criteria(1.0), opt.sliverAngle, &o);
  std::vector<Tr::Cell_handle> one, two;
  runOnThreads(1, [&] { one = cgal::sequential::badCellsOf(c3t3, criteria); });
  runOnThreads(2, [&] { two = cgal::sequential::badCellsOf(c3t3, criteria); });
  EXPECT_TRUE(one == two) << "the same cells in the same order on one and two threads";
  std::set<Tr::Cell_handle> expected;
  for (auto c = c3t3.cells_in_complex_begin(); c != c3t3.cells_in_complex_end(); ++c)
    if (criteria.cell_criteria_object()(c3t3.triangulation(), c))
      expected.insert(c);
  ASSERT_GT(expected.size(), 10u) << "the stricter size bound refuses some cells";
  EXPECT_LT(expected.size(), c3t3.number_of_cells_in_complex()) << "and keeps others";
  EXPECT_TRUE(std::vector<Tr::Cell_handle>(expected.begin(), expected.end()) == one)
    << "every refused cell once, sorted, and no other";
}

TEST(MeshingPhases, ThePerturberIsSkippedWhereEveryCellIsAboveItsBound)
{
  // Picked refinement points leave every cell above 12 degrees here: the perturber would move
  // nothing, so it is not called; the statistics say so, and the run stays valid and complete.
  const HierarchicalOracle o = unitCube();
  const FeatureSegments edges = test::cubeEdges(0, 1);
  const TetMesh m = meshOracle(o, edges, {}, cubeOptions(0.15));
  ASSERT_GT(m.statistics.at("optimisation.min_dihedral_before"), 12.0);
  EXPECT_EQ(m.statistics.at("optimisation.perturbation_steps"), 0.0);
  EXPECT_EQ(m.statistics.at("optimisation.perturbation_last_bound"), 12.0);
  EXPECT_EQ(m.statistics.at("optimisation.perturbation_skipped"), 1.0);
  EXPECT_EQ(m.statistics.at("validity.defects"), 0.0);
  EXPECT_NEAR(featureCoverage(m.segments, edges), 1.0, 1e-12);
  // where picking is off, circumcentres leave slivers below 12 degrees: the perturber runs
  MesherOptions circumcentres = cubeOptions(0.15);
  circumcentres.pickingSliverAngle = 0.0;
  const TetMesh c = meshOracle(o, edges, {}, circumcentres);
  ASSERT_LE(c.statistics.at("optimisation.min_dihedral_before"), 12.0);
  EXPECT_GT(c.statistics.at("optimisation.perturbation_steps"), 0.0);
  EXPECT_EQ(c.statistics.at("optimisation.perturbation_skipped"), 0.0);
}
