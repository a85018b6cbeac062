// SPDX-License-Identifier: GPL-3.0-or-later
// The phases of the feature-line search called one by one (findFeatureLines runs them in order):
// the grid search's crossings, the curve graph's chains and junctions, and the junction phase.
#include "BoxDomain.h"
#include "FeatureCurveGraph.h"
#include "FeatureGridSearch.h"
#include "FeatureJunctions.h"
#include "HalfSpaceDomain.h"
#include "HierarchicalOracle.h"
#include "SphereDomain.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>
#include <vector>

using namespace omesh;
using namespace omesh::featurelines;

namespace
{
/// A ball around c cut away above z = cutAt: its rim, a circle, is the one curve.
HierarchicalOracle cutBall(const Vec3& c, double r, double cutAt)
{
  HierarchicalOracle o;
  auto cut = std::make_shared<HalfSpaceDomain>(Vec3{ 0, 0, cutAt }, Vec3{ 0, 0, -1 }, 0, "cut");
  cut->setCut(true);
  o.add(cut);
  o.add(std::make_shared<SphereDomain>(c, r, 1, "ball"));
  return o;
}

/// Material 3 on top of 1 and 2 side by side: four regions (the outside counts) meet at (2, 0, 2)
/// and (2, 2, 2), where four curves end, and the curve of 1, 2 and 3 joins those two junctions.
HierarchicalOracle threeBoxes()
{
  HierarchicalOracle o;
  o.add(std::make_shared<BoxDomain>(Vec3{ 0, 0, 2 }, Vec3{ 4, 2, 4 }, 3, "top"));
  o.add(std::make_shared<BoxDomain>(Vec3{ 0, 0, 0 }, Vec3{ 2, 2, 2 }, 1, "left"));
  o.add(std::make_shared<BoxDomain>(Vec3{ 2, 0, 0 }, Vec3{ 4, 2, 2 }, 2, "right"));
  return o;
}

std::vector<int> junctionsOf(const FeatureCurveGraph& graph)
{
  std::vector<int> j;
  for (int v = graph.crossingCount(); v < static_cast<int>(graph.nodes().size()); ++v)
    j.push_back(v);
  return j;
}
}

TEST(FeatureLinePhases, GridSearchFindsTheRimOfACutBallOnTheCircleAsOneLoop)
{
  const Vec3 c{ 0.1, 0.2, 0.3 };
  const double r = 1.0, cutAt = 0.65;
  const HierarchicalOracle oracle = cutBall(c, r, cutAt);
  FeatureLineOptions options;
  options.maxSegmentLength = 0.15;
  std::vector<std::string> warnings;
  FeatureGridSearch grid(oracle, options, warnings);
  const GridCrossings found = grid.search();
  EXPECT_TRUE(warnings.empty());
  EXPECT_DOUBLE_EQ(found.spacing, 0.5 * options.maxSegmentLength);
  ASSERT_GT(found.gridFacesCrossed, 8u);
  EXPECT_GE(found.crossings.size(), found.gridFacesCrossed);
  for (const Crossing& x : found.crossings)
  {
    EXPECT_NEAR(x.point.z, cutAt, 1e-6);
    EXPECT_NEAR(norm(x.point - c), r, 1e-6);
    EXPECT_EQ(materialsOf(x.regions), (std::vector<int>{ kOutside, 1 }));
  }
  EXPECT_TRUE(found.junctions.empty());
  // a loop: every crossing linked twice
  std::vector<int> links(found.crossings.size(), 0);
  for (const Link& l : found.links)
    ++links[l.a], ++links[l.b];
  for (int n : links)
    EXPECT_EQ(n, 2);

  const FeatureCurveGraph graph(found);
  EXPECT_TRUE(junctionsOf(graph).empty());
  const std::vector<std::vector<int>> chains = graph.curves();
  ASSERT_EQ(chains.size(), 1u);
  EXPECT_EQ(chains[0].front(), chains[0].back());
  EXPECT_EQ(chains[0].size(), found.crossings.size() + 1);
}

TEST(FeatureLinePhases, JunctionsOfThreeBoxesAreWhereFourRegionsMeetAndAShortCurveCollapsesThem)
{
  const HierarchicalOracle oracle = threeBoxes();
  std::vector<std::string> warnings;
  const GridCrossings found = FeatureGridSearch(oracle, {}, warnings).search();
  FeatureCurveGraph graph(found);
  const std::vector<int> junctions = junctionsOf(graph);
  ASSERT_EQ(junctions.size(), 2u);
  for (const Vec3& known : { Vec3{ 2, 0, 2 }, Vec3{ 2, 2, 2 } })
  {
    int near = 0;
    for (int j : junctions)
      near += norm(graph.nodes()[j] - known) < 1e-6;
    EXPECT_EQ(near, 1) << "no junction at (" << known.x << ", " << known.y << ", " << known.z << ")";
  }
  std::vector<std::vector<int>> chains = graph.curves();
  trimArms(graph, chains);
  const size_t curves = chains.size();
  // no chord length: nothing collapses
  collapseShortCurves(graph, chains, found.crossings, {});
  EXPECT_EQ(chains.size(), curves);
  // the curve of 1, 2 and 3 between the junctions (length 2) is shorter than a chord of 3: one
  // vertex at the middle of the two, the curve gone, every other curve still ending there
  FeatureLineOptions coarse;
  coarse.maxSegmentLength = 3.0;
  collapseShortCurves(graph, chains, found.crossings, coarse);
  ASSERT_EQ(chains.size(), curves - 1);
  EXPECT_LT(norm(graph.nodes()[junctions[0]] - Vec3{ 2, 1, 2 }), 1e-6);
  int ends = 0;
  for (const auto& chain : chains)
  {
    EXPECT_NE(chain.front(), junctions[1]);
    EXPECT_NE(chain.back(), junctions[1]);
    ends += (chain.front() == junctions[0]) + (chain.back() == junctions[0]);
  }
  EXPECT_EQ(ends, 6);
}
