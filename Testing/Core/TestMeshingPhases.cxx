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

/// Runs the exuder on every cell, undoes it and expects the complex from before it: the same
/// tetrahedra with the same materials, interfaces, features and vertex dimensions. Returns how many
/// materials the mesh has.
std::size_t expectUndoGivesBackTheMeshFromBeforeTheExuder(const HierarchicalOracle& o, const FeatureSegments& edges,
  const MesherOptions& options, std::size_t corners)
{
  MesherOptions noExuder = options;
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
  EXPECT_TRUE(exudation.before.has_value());
  run.optimisation.undo(exudation, "asked by the test");
  run.optimisation.finish();
  const TetMesh undone = run.finish();
  EXPECT_GT(undone.statistics.at("optimisation.exudation_steps"), 0.0);
  EXPECT_TRUE(hasWarning(undone, "exudation undone: asked by the test"));
  EXPECT_FALSE(hasWarning(undone, "incomplete"));
  EXPECT_EQ(undone.tets.size(), before.tets.size());
  EXPECT_TRUE(tetSet(undone) == tetSet(before)) << "the undo changed the mesh (or a material) from before the exuder";
  EXPECT_EQ(undone.interfaceTriangles.size(), before.interfaceTriangles.size());
  if (!edges.empty())
    EXPECT_NEAR(featureCoverage(undone.segments, edges), 1.0, 1e-12);
  EXPECT_EQ(undone.statistics.at("validity.defects"), 0.0);
  EXPECT_EQ(static_cast<std::size_t>(std::count(undone.pointDimension.begin(), undone.pointDimension.end(), 0)), corners)
    << "the vertices' dimensions came back";

  // and the exuder itself changed the mesh: the undo had something to undo
  MeshingRun kept(o, edges, pumped);
  kept.initial.run({});
  kept.refinement.refineAllLevels();
  kept.optimisation.start();
  kept.optimisation.perturbKeepingSegments();
  kept.optimisation.exude();
  kept.optimisation.finish();
  EXPECT_FALSE(tetSet(kept.finish()) == tetSet(before)) << "the exuder changed nothing: nothing to undo";
  return std::set<int>(undone.tetMaterial.begin(), undone.tetMaterial.end()).size();
}

TEST(MeshingPhases, UndoneExudationGivesBackTheMeshFromBeforeIt)
{
  // The undo rebuilds the complex from a compact record (ComplexSnapshot.h); real inputs rarely
  // need it, so it is called here and compared with a run that stops before the exuder.
  expectUndoGivesBackTheMeshFromBeforeTheExuder(unitCube(), test::cubeEdges(0, 1), cubeOptions(0.2), 8);
}

TEST(MeshingPhases, UndoneExudationGivesBackEveryMaterial)
{
  // The record keeps the labels of the cells beside a wall (an interface, or two materials
  // meeting) and floods them through the others: three materials, two of them nested, none of
  // them reached from the outside without crossing a wall.
  HierarchicalOracle o;
  o.add(std::make_shared<SurfaceDomain>(test::icosphere({ 0.5, 0.5, 0.5 }, 0.2, 2), 3));
  o.add(std::make_shared<SurfaceDomain>(test::cube(0.15, 0.85), 2));
  o.add(std::make_shared<SurfaceDomain>(test::cube(0, 1), 1));
  EXPECT_EQ(expectUndoGivesBackTheMeshFromBeforeTheExuder(o, {}, cubeOptions(0.12), 0), 3u);
}

TEST(MeshingPhases, CellsHoldSurfaceCentresOnlyBesideTheSurface)
{
  // SurfaceCentreCell3: the centres out of line, set on both cells of every surface facet, the
  // block absent from most cells, and the cell far smaller than CGAL's compact one.
  using CgalCell = CGAL::Compact_mesh_cell_generator_3<omesh::cgal::GeomTraits, omesh::cgal::MeshDomain::Subdomain_index,
    omesh::cgal::MeshDomain::Surface_patch_index, omesh::cgal::MeshDomain::Index>::Rebind_TDS<Tr::Triangulation_data_structure>::Other;
  static_assert(sizeof(Tr::Cell) + 120 <= sizeof(CgalCell), "the centres are out of line");
  HierarchicalOracle o;
  o.add(std::make_shared<SurfaceDomain>(test::icosphere({ 0.5, 0.5, 0.5 }, 0.3, 2), 2));
  o.add(std::make_shared<SurfaceDomain>(test::cube(0, 1), 1));
  const FeatureSegments edges = test::cubeEdges(0, 1);
  const MesherOptions options = cubeOptions(0.1); // the run keeps references to its inputs
  MeshingRun run(o, edges, options);
  run.initial.run({});
  run.refinement.refineAllLevels();
  const Tr& tr = run.context.c3t3->triangulation();
  std::size_t cells = 0, holding = 0, surfaceFacets = 0;
  for (auto c = tr.all_cells_begin(); c != tr.all_cells_end(); ++c)
  {
    ++cells;
    holding += c->holds_surface_centres();
    for (int i = 0; i < 4; ++i)
    {
      if (!c->is_facet_on_surface(i))
        continue;
      ++surfaceFacets;
      ASSERT_TRUE(c->holds_surface_centres());
      const auto mirror = tr.mirror_facet(std::make_pair(Tr::Cell_handle(c), i));
      EXPECT_EQ(c->get_facet_surface_center(i), mirror.first->get_facet_surface_center(mirror.second));
      EXPECT_TRUE(c->get_facet_surface_center_index(i) == mirror.first->get_facet_surface_center_index(mirror.second));
    }
  }
  EXPECT_GT(surfaceFacets, 100u);
  EXPECT_LT(2 * holding, cells) << "most cells are away from the surface and hold no centres";

  // a copy holds its own centres
  auto c = tr.finite_cells_begin();
  while (!c->holds_surface_centres())
    ++c;
  Tr::Cell copy(*c);
  copy.set_facet_surface_center(0, Tr::Cell::Point_3(9, 9, 9));
  EXPECT_NE(c->get_facet_surface_center(0), copy.get_facet_surface_center(0));
  for (int i = 1; i < 4; ++i)
    EXPECT_EQ(c->get_facet_surface_center(i), copy.get_facet_surface_center(i));
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
