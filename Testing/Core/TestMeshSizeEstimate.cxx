// SPDX-License-Identifier: GPL-3.0-or-later
#include "InputError.h"
#include "HierarchicalOracle.h"
#include "MeshSizeEstimate.h"
#include "OracleMesher.h"
#include "SphereDomain.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace omesh;

namespace
{
HierarchicalOracle ball()
{
  HierarchicalOracle o;
  o.add(std::make_shared<SphereDomain>(Vec3{ 0, 0, 0 }, 1.0, 1, "ball"));
  return o;
}

MaterialCriteria sizes(double cell, double facet)
{
  MaterialCriteria c;
  c.global.cellSize = cell;
  c.global.facetSize = facet;
  c.global.facetDistance = cell / 20;
  c.global.cellRadiusEdgeRatio = 3;
  return c;
}
}

// The estimate is for refusing meshes that cannot fit in memory: it must be within a small factor
// of what the mesher makes, and follow the criteria (cubes for cells, squares for facets).
TEST(MeshSizeEstimate, IsWithinASmallFactorOfTheMeshTheCriteriaGive)
{
  const HierarchicalOracle o = ball();
  for (double h : { 0.4, 0.2 })
  {
    MesherOptions opt;
    opt.criteria = sizes(h, h);
    opt.perturb = opt.exude = false;
    opt.seed = 3;
    const double made = static_cast<double>(meshOracle(o, {}, {}, opt).points.size());
    const double estimate = estimateMeshVertices(o, opt.criteria, {});
    EXPECT_GT(estimate, made / 4) << "h " << h;
    EXPECT_LT(estimate, made * 4) << "h " << h;
  }
}

TEST(MeshSizeEstimate, FollowsTheCriteria)
{
  const HierarchicalOracle o = ball();
  const double coarse = estimateMeshVertices(o, sizes(0.2, 0.2), {});
  EXPECT_NEAR(estimateMeshVertices(o, sizes(0.1, 1.0), {}) / estimateMeshVertices(o, sizes(0.2, 1.0), {}), 8.0, 0.5);
  EXPECT_GT(estimateMeshVertices(o, sizes(0.2, 1e-9), {}), 1e15); // the hang of issue 14
  FeatureSegments line;
  line.points = { { -1, 0, 0 }, { 1, 0, 0 } };
  line.segments = { { 0, 1 } };
  MaterialCriteria withEdge = sizes(0.2, 0.2);
  withEdge.global.edgeSize = 1e-6;
  EXPECT_GT(estimateMeshVertices(o, withEdge, line), coarse + 1e6);
}

// A line's own edge size (the per-feature level) counts, not the global one.
TEST(MeshSizeEstimate, FeatureLinesCountAtTheirOwnEdgeSize)
{
  const HierarchicalOracle o = ball();
  FeatureSegments line;
  line.points = { { -1, 0, 0 }, { 1, 0, 0 } };
  line.segments = { { 0, 1 } };
  MaterialCriteria c = sizes(0.2, 0.2);
  c.global.edgeSize = 0.5;
  const double global = estimateMeshVertices(o, c, line);
  line.edgeSizes = { 1e-6 };
  EXPECT_NEAR(estimateMeshVertices(o, c, line) - global, 2.0 / 1e-6 - 2.0 / 0.5, 1.0);
}

// Criteria the run cannot meet are refused before meshing, with the numbers and the fix; criteria
// within reach pass.
TEST(MeshSizeCheck, RefusesBeyondTenTimesTheBudgetNamingTheCriterionAndFactor)
{
  const HierarchicalOracle o = ball();
  const MeshSizeEstimate fine = estimateMeshSize(o, sizes(0.2, 0.2), {});
  EXPECT_NO_THROW(checkMeshSize(fine, 2e6, kDefaultTimeLimit));
  EXPECT_NO_THROW(checkMeshSize(fine, 0, 0)); // no budget, no limit
  const MeshSizeEstimate tiny = estimateMeshSize(o, sizes(1, 1e-6), {});
  EXPECT_GT(tiny.surfaces, tiny.volume);
  try
  {
    checkMeshSize(tiny, 2e6, kDefaultTimeLimit);
    FAIL() << "not refused";
  }
  catch (const InputError& e)
  {
    const std::string m = e.what();
    EXPECT_NE(m.find("vertex budget of 2e+06"), std::string::npos) << m;
    EXPECT_NE(m.find("FacetSize about"), std::string::npos) << m;
    EXPECT_EQ(m.find("CellSize about"), std::string::npos) << m; // the volume asks for little
  }
  // within 10x the budget: refinement runs and stops at the budget with a warning
  EXPECT_NO_THROW(checkMeshSize(MeshSizeEstimate{ 5e6, 0, 0 }, 2e6, 0));
}

TEST(MeshSizeCheck, RefusesWhatTheTimeLimitCannotHoldWithoutABudget)
{
  const MeshSizeEstimate many{ 1e12, 0, 0 };
  try
  {
    checkMeshSize(many, 0, kDefaultTimeLimit);
    FAIL() << "not refused";
  }
  catch (const InputError& e)
  {
    const std::string m = e.what();
    EXPECT_NE(m.find("time limit of 600 s"), std::string::npos) << m;
    EXPECT_NE(m.find("CellSize about"), std::string::npos) << m;
  }
  EXPECT_NO_THROW(checkMeshSize(many, 0, 0)); // no limit asked for: the user's call
}

// A size larger than the domain or 1000x smaller than it is a slip worth a warning with both numbers;
// criteria in scale say nothing, and a material repeating the global value is not warned twice.
TEST(CriteriaScaleWarnings, NameSizesLargerThanTheDomainOrAThousandTimesSmaller)
{
  const HierarchicalOracle o = ball(); // diagonal 2 sqrt(3) = 3.464
  EXPECT_TRUE(criteriaScaleWarnings(o, sizes(0.2, 0.2)).empty());
  MaterialCriteria metres = sizes(20, 20);
  metres.perMaterial[1].cellSize = 20; // the global value again
  std::vector<std::string> w = criteriaScaleWarnings(o, metres);
  ASSERT_EQ(w.size(), 1u);
  EXPECT_NE(w[0].find("CellSize 20 and FacetSize 20 are larger"), std::string::npos) << w[0];
  EXPECT_NE(w[0].find("3.464"), std::string::npos) << w[0];
  MaterialCriteria tiny = sizes(0.2, 0.2);
  tiny.perMaterial[1].edgeSize = 1e-4;
  w = criteriaScaleWarnings(o, tiny);
  ASSERT_EQ(w.size(), 1u);
  EXPECT_NE(w[0].find("material 1: EdgeSize 0.0001 is up to 3.464e+04 times smaller"), std::string::npos) << w[0];
  // a facet distance far below the domain is a precise surface, not a slip; above it, a slip
  MaterialCriteria precise = sizes(0.2, 0.2);
  precise.global.facetDistance = 1e-6;
  EXPECT_TRUE(criteriaScaleWarnings(o, precise).empty());
  precise.global.facetDistance = 5;
  EXPECT_EQ(criteriaScaleWarnings(o, precise).size(), 1u);
}

// Only -1 (or no value) means "not set": a typed -2 is an error naming the criterion, not "no bound".
TEST(MeshCriteria, OnlyMinusOneIsUnsetOtherNegativesAreErrors)
{
  const MeshCriteria c = MeshCriteria::fromVtk({ 25, -1, 0, -2, 3, -1 });
  EXPECT_FALSE(c.facetSize.has_value());
  EXPECT_FALSE(c.edgeSize.has_value());
  ASSERT_TRUE(c.cellSize.has_value());
  try
  {
    c.check("global criteria");
    FAIL() << "a negative cell size passed";
  }
  catch (const InputError& e)
  {
    const std::string m = e.what();
    EXPECT_NE(m.find("global criteria: CellSize (cell_size) is -2"), std::string::npos) << m;
    EXPECT_NE(m.find("cannot be negative"), std::string::npos) << m;
  }
  EXPECT_THROW(MeshCriteria::fromVtk({ 25, std::nan(""), 0, 1, 3, 0 }).check("x"), InputError);
  EXPECT_NO_THROW(MeshCriteria::fromVtk({ -1, -1, -1, -1, -1, -1 }).check("x"));
  // unset global values are the defaults
  MaterialCriteria merged = mergeCriteria(MeshCriteria::fromVtk({ -1, 2, -1, -1, -1, -1 }), {});
  EXPECT_EQ(merged.globalValues().facetAngle, MeshCriteria::defaults().facetAngle.value());
  EXPECT_EQ(merged.globalValues().facetSize, 2.0);
}
