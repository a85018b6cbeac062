// SPDX-License-Identifier: GPL-3.0-or-later
#include "HierarchicalOracle.h"
#include "MeshSizeEstimate.h"
#include "OracleMesher.h"
#include "SphereDomain.h"

#include <gtest/gtest.h>

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
