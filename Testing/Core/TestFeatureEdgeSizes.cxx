// SPDX-License-Identifier: GPL-3.0-or-later
// The per-feature level of the edge size: the merge rule (global < per material < per feature),
// its errors, and the mesher keeping each line's own bound.
#include "BoxDomain.h"
#include "FeatureEdgeSizes.h"
#include "FeatureMerge.h"
#include "HierarchicalOracle.h"
#include "InputError.h"
#include "MeshQuality.h"
#include "OracleMesher.h"
#include "SurfaceDomain.h"
#include "TestShapes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

using namespace omesh;

namespace
{
MaterialCriteria criteria(double global, std::map<int, std::optional<double>> perMaterial)
{
  MaterialCriteria c;
  c.global.edgeSize = global;
  for (const auto& [m, e] : perMaterial)
  {
    MeshCriteria own = MeshCriteria::inheritAll();
    own.edgeSize = e;
    own.cellSize = 1.0; // another criterion set: the material is listed without an edge size of its own
    c.perMaterial[m] = own;
  }
  return c;
}

/// Two cube edges that share no point: line A along x at y = z = 0, line B along x at y = z = 1.
FeatureSegments twoCubeEdges(std::optional<double> a, std::optional<double> b)
{
  FeatureSegments f;
  f.points = { { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 1 }, { 1, 1, 1 } };
  f.segments = { { 0, 1 }, { 2, 3 } };
  f.edgeSizes = { a, b };
  return f;
}

template <class F>
std::string inputError(F&& f)
{
  try
  {
    f();
  }
  catch (const InputError& e)
  {
    return e.what();
  }
  return "";
}

/// Longest mesh edge along input segment `input` (pieces from locateFeatureSegments).
double longestPiece(const TetMesh& m, int input)
{
  double longest = 0.0;
  for (const auto& s : m.segments)
    if (s.input == input)
      longest = std::max(longest, norm(s.b - s.a));
  return longest;
}
}

TEST(FeatureEdgeSizes, MergeRuleOwnBeforeMaterialsBeforeGlobal)
{
  const MaterialCriteria c = criteria(0.5, { { 1, 0.2 }, { 2, 0.3 }, { 3, 0.0 }, { 4, std::nullopt } });
  // per feature: the line's own value wins, also over a finer material and a 0 (no bound) of its own
  EXPECT_EQ(featureEdgeSize(0.7, { 1, 2 }, c), 0.7);
  EXPECT_EQ(featureEdgeSize(0.0, { 1 }, c), 0.0);
  // per material: the finest of the materials the line separates
  EXPECT_EQ(featureEdgeSize(std::nullopt, { 1, 2 }, c), 0.2);
  EXPECT_EQ(featureEdgeSize(std::nullopt, { 2 }, c), 0.3);
  // 0 (no bound) is the coarsest: a positive bound of the other side is finer; alone it counts
  EXPECT_EQ(featureEdgeSize(std::nullopt, { 2, 3 }, c), 0.3);
  EXPECT_EQ(featureEdgeSize(std::nullopt, { 3 }, c), 0.0);
  // global: no material with an edge size of its own (material 4 sets only a cell size), outside, none
  EXPECT_EQ(featureEdgeSize(std::nullopt, { 4 }, c), 0.5);
  EXPECT_EQ(featureEdgeSize(std::nullopt, { kOutside }, c), 0.5);
  EXPECT_EQ(featureEdgeSize(std::nullopt, {}, c), 0.5);
  EXPECT_TRUE(hasMaterialEdgeSizes(c));
  EXPECT_FALSE(hasMaterialEdgeSizes(criteria(0.5, { { 4, std::nullopt } })));
}

TEST(FeatureEdgeSizes, AnEdgeOfABoxSeparatesItsMaterialFromTheOneAround)
{
  HierarchicalOracle o;
  o.add(std::make_shared<BoxDomain>(Vec3{ 0, 0, 0 }, Vec3{ 1, 1, 1 }, 1, "inner"));
  o.add(std::make_shared<BoxDomain>(Vec3{ -1, -1, -1 }, Vec3{ 2, 2, 2 }, 2, "outer"));
  EXPECT_EQ(materialsAroundSegment(o, { 0, 0, 0 }, { 1, 0, 0 }), (std::vector<int>{ 1, 2 }));
  EXPECT_EQ(materialsAroundSegment(o, { -1, -1, -1 }, { 2, -1, -1 }), (std::vector<int>{ 2 })); // the outer box's rim
  EXPECT_EQ(materialsAroundSegment(o, { 0.2, 0.5, 0.5 }, { 0.8, 0.5, 0.5 }), (std::vector<int>{ 1 }));

  // the inner box's own edge size applies to its edges, the outer's to its rim, a line's own wins
  FeatureSegments f;
  f.points = { { 0, 0, 0 }, { 1, 0, 0 }, { -1, -1, -1 }, { 2, -1, -1 }, { 0, 1, 1 }, { 1, 1, 1 } };
  f.segments = { { 0, 1 }, { 2, 3 }, { 4, 5 } };
  f.edgeSizes = { std::nullopt, std::nullopt, 0.05 };
  EXPECT_EQ(resolveFeatureEdgeSizes(f, criteria(0.5, { { 1, 0.1 }, { 2, 0.3 } }), o), (std::vector<double>{ 0.1, 0.3, 0.05 }));
  // without own values or material edge sizes: the global one everywhere
  f.edgeSizes.clear();
  EXPECT_EQ(resolveFeatureEdgeSizes(f, criteria(0.5, {}), o), (std::vector<double>{ 0.5, 0.5, 0.5 }));
}

TEST(FeatureEdgeSizes, InvalidOwnValuesAreInputErrorsNamingTheSegment)
{
  HierarchicalOracle o;
  o.add(std::make_shared<BoxDomain>(Vec3{ 0, 0, 0 }, Vec3{ 1, 1, 1 }, 1));
  for (double bad : { -0.5, std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity() })
  {
    const FeatureSegments f = twoCubeEdges(0.1, bad);
    const std::string e = inputError([&] { f.validate(o, 3.0); });
    EXPECT_NE(e.find("segment 1 (0, 1, 1) - (1, 1, 1) has EdgeSize"), std::string::npos) << e;
    MesherOptions options;
    options.criteria.global.cellSize = 0.5;
    EXPECT_EQ(inputError([&] { meshOracle(o, f, {}, options); }), e);
  }
  FeatureSegments f = twoCubeEdges(0.1, 0.2);
  f.edgeSizes.pop_back();
  EXPECT_NE(inputError([&] { f.validate(o, 3.0); }).find("1 edge sizes for 2 segments"), std::string::npos);
}

TEST(FeatureEdgeSizes, OneLineGivenTwoDifferentValuesIsAContradiction)
{
  // the same segment twice (two files, or one drawn twice), reversed
  FeatureSegments twice;
  twice.points = { { 0, 0, 0 }, { 1, 0, 0 }, { 1, 0, 0 }, { 0, 0, 0 } };
  twice.segments = { { 0, 1 }, { 2, 3 } };
  twice.edgeSizes = { 0.1, 0.2 };
  const std::string e = inputError([&] { mergeFeatureSegments(twice); });
  EXPECT_NE(e.find("segment (1, 0, 0) - (0, 0, 0) gets EdgeSize 0.1 and 0.2"), std::string::npos) << e;

  // the same value, or one unset, is no contradiction: the merged line keeps it
  twice.edgeSizes = { std::nullopt, 0.2 };
  mergeFeatureSegments(twice);
  ASSERT_EQ(twice.segments.size(), 1u);
  EXPECT_EQ(twice.edgeSizes, (std::vector<std::optional<double>>{ 0.2 }));

  // overlapping collinear lines: each piece of their union keeps the value of what covers it
  FeatureSegments overlap;
  overlap.points = { { 0, 0, 0 }, { 2, 0, 0 }, { 1, 0, 0 }, { 3, 0, 0 } };
  overlap.segments = { { 0, 1 }, { 2, 3 } };
  overlap.edgeSizes = { 0.1, std::nullopt };
  mergeFeatureSegments(overlap);
  ASSERT_EQ(overlap.segments.size(), 3u);
  ASSERT_EQ(overlap.edgeSizes.size(), 3u);
  for (size_t s = 0; s < 3; ++s)
  {
    const double x = 0.5 * (overlap.points[overlap.segments[s][0]].x + overlap.points[overlap.segments[s][1]].x);
    EXPECT_EQ(overlap.edgeSizes[s], x < 2 ? std::optional<double>(0.1) : std::nullopt) << "piece at x = " << x;
  }
  overlap.edgeSizes = { 0.1, 0.3 };
  overlap.points = { { 0, 0, 0 }, { 2, 0, 0 }, { 1, 0, 0 }, { 3, 0, 0 } };
  overlap.segments = { { 0, 1 }, { 2, 3 } };
  EXPECT_NE(inputError([&] { mergeFeatureSegments(overlap); }).find("gets EdgeSize 0.1 and 0.3"), std::string::npos);
}

TEST(FeatureEdgeSizes, EachLineKeepsItsOwnEdgeSizeInTheMesh)
{
  HierarchicalOracle o;
  o.add(std::make_shared<SurfaceDomain>(test::cube(0, 1), 1));
  const FeatureSegments lines = twoCubeEdges(0.1, 0.4);
  for (FeatureStrategy strategy : { FeatureStrategy::Conforming, FeatureStrategy::ProtectingBalls })
  {
    SCOPED_TRACE(toString(strategy));
    MesherOptions options;
    options.strategy = strategy;
    options.criteria.global = { 25.0, 0.5, 0.05, 0.5, 3.0, 0.25 }; // a global edge size between the lines'
    options.seed = 3;
    const TetMesh m = meshOracle(o, lines, {}, options);
    EXPECT_NEAR(featureCoverage(m.segments, lines), 1.0, 1e-12); // every piece is a mesh edge
    for (const auto& s : m.segments)
      EXPECT_TRUE(s.present);
    EXPECT_LE(longestPiece(m, 0), 0.1 * (1 + 1e-9));
    EXPECT_LE(longestPiece(m, 1), 0.4 * (1 + 1e-9));
    EXPECT_GT(longestPiece(m, 1), 0.1) << "line B was meshed at line A's edge size";
    EXPECT_NEAR(materialVolumes(m).at(1), 1.0, 0.05); // the ten cube edges without lines are chamfered
  }
}
