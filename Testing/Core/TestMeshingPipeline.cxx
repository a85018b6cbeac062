// SPDX-License-Identifier: GPL-3.0-or-later
// The core's one entry point (runMeshingPipeline): what the VTK filter used to run itself before
// and after the mesher, reachable from C++ alone.
#include "HierarchicalOracle.h"
#include "InputError.h"
#include "MeshQuality.h"
#include "MeshingPipeline.h"
#include "SphereDomain.h"
#include "SurfaceDomain.h"
#include "TestShapes.h"

#include <gtest/gtest.h>

#include <algorithm>

using namespace omesh;

namespace
{
bool anyWarning(const std::vector<std::string>& warnings, const std::string& text)
{
  return std::any_of(warnings.begin(), warnings.end(), [&](const std::string& w) { return w.find(text) != std::string::npos; });
}

PipelineOptions coarse()
{
  PipelineOptions o;
  o.mesher.criteria.global = { 25.0, 0.3, 0.02, 0.3, 2.0, 0.0 };
  o.mesher.seed = 1;
  return o;
}
}

TEST(MeshingPipeline, GivenLinesAreClippedAndMergedWithAWarningAndKept)
{
  HierarchicalOracle oracle;
  oracle.add(std::make_shared<SurfaceDomain>(test::cube(-1, 1), 1, "cube"));
  PipelineInput input;
  input.lines = test::cubeEdges(-1, 1);
  const FeatureSegments twice = test::cubeEdges(-1, 1); // every edge given twice
  const int offset = static_cast<int>(input.lines.points.size());
  input.lines.points.insert(input.lines.points.end(), twice.points.begin(), twice.points.end());
  for (const auto& s : twice.segments)
    input.lines.segments.push_back({ s[0] + offset, s[1] + offset });
  // and a line far outside the cube: no material there
  input.lines.points.push_back({ 5, 5, 5 });
  input.lines.points.push_back({ 6, 5, 5 });
  const int n = static_cast<int>(input.lines.points.size());
  input.lines.segments.push_back({ n - 2, n - 1 });

  const PipelineResult r = runMeshingPipeline(oracle, input, coarse());
  EXPECT_TRUE(anyWarning(r.mesh.warnings, "feature lines clipped to the meshed domain: 1 segment(s) removed"));
  EXPECT_TRUE(anyWarning(r.mesh.warnings, "duplicate segment(s)"));
  EXPECT_EQ(r.selection.segments.segments.size(), 12u) << "the twelve edges, once each";
  EXPECT_NEAR(featureCoverage(locateFeatureSegments(r.mesh, r.selection.segments), r.selection.segments), 1.0, 1e-12);
  EXPECT_EQ(r.mesh.statistics.at("validity.defects"), 0.0);
  EXPECT_GT(r.mesh.statistics.at("estimated_vertices"), 0.0);
}

TEST(MeshingPipeline, FoundLinesTakeTheFirstTenthOfTheProgress)
{
  HierarchicalOracle oracle;
  oracle.add(std::make_shared<SphereDomain>(Vec3{ 0.3, 0, 0 }, 0.5, 2, "ball"));
  oracle.add(std::make_shared<SurfaceDomain>(test::cube(-1, 1), 1, "cube"));
  PipelineOptions o = coarse();
  o.features = FeatureSource::Automatic; // the cube's edges and the ball's rim where it leaves the cube
  std::vector<double> search, mesher;
  o.mesher.progress = [&](double f, const char* phase) {
    (std::string(phase) == "feature line search" ? search : mesher).push_back(f);
    return true;
  };
  const PipelineResult r = runMeshingPipeline(oracle, {}, o);
  EXPECT_FALSE(r.selection.automatic.segments.empty());
  ASSERT_FALSE(search.empty());
  ASSERT_FALSE(mesher.empty());
  EXPECT_LE(*std::max_element(search.begin(), search.end()), 0.1 + 1e-12);
  EXPECT_GE(*std::min_element(mesher.begin(), mesher.end()), 0.1 - 1e-12);
  EXPECT_NEAR(featureCoverage(locateFeatureSegments(r.mesh, r.selection.segments), r.selection.segments), 1.0, 1e-12);
}

TEST(MeshingPipeline, AnEmptyMeshIsAnErrorSayingWhatTheRunFound)
{
  HierarchicalOracle oracle;
  auto cut = std::make_shared<SphereDomain>(Vec3{ 0, 0, 0 }, 0.5, 2, "ball");
  cut->setCut(true);
  oracle.add(cut);
  oracle.add(std::make_shared<SphereDomain>(Vec3{ 0, 0, 0 }, 0.4, 1, "inner"));
  try
  {
    runMeshingPipeline(oracle, {}, coarse());
    FAIL() << "an empty mesh was accepted";
  }
  catch (const InputError& e)
  {
    EXPECT_NE(std::string(e.what()).find("no tetrahedra"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("inner is hidden"), std::string::npos) << e.what();
  }
}

TEST(MeshingPipeline, QuadraticElementsWithOrderTwo)
{
  HierarchicalOracle oracle;
  oracle.add(std::make_shared<SphereDomain>(Vec3{ 0, 0, 0 }, 1.0, 1, "ball"));
  PipelineOptions o = coarse();
  o.mesher.elementOrder = 2;
  const PipelineResult r = runMeshingPipeline(oracle, {}, o);
  EXPECT_EQ(r.quadratic.tets.size(), r.mesh.tets.size());
  EXPECT_TRUE(r.mesh.statistics.count("time.quadratic"));
}
