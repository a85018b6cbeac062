// SPDX-License-Identifier: GPL-3.0-or-later
// Feature lines as users produce them: repeated points, duplicate and overlapping collinear segments
// are merged (issue 14), crossings are left for FeatureSegments::validate to refuse.
#include "FeatureMerge.h"
#include "HierarchicalOracle.h"
#include "InputError.h"
#include "SphereDomain.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>

using namespace omesh;

namespace
{
/// Total length of the segments.
double totalLength(const FeatureSegments& f)
{
  double sum = 0;
  for (size_t s = 0; s < f.segments.size(); ++s)
    sum += f.length(s);
  return sum;
}

HierarchicalOracle ballOracle()
{
  HierarchicalOracle oracle;
  oracle.add(std::make_shared<SphereDomain>(Vec3{ 0, 0, 0 }, 5.0, 1, "ball"));
  return oracle;
}
}

TEST(FeatureMerge, DuplicatesAndOverlapsBecomeTheirUnion)
{
  FeatureSegments f;
  // (-2,0,0)-(2,0,0) twice (once reversed, once through a repeated point), (-1,0,0)-(3,0,0) overlapping
  f.points = { { -2, 0, 0 }, { 2, 0, 0 }, { -1, 0, 0 }, { 3, 0, 0 }, { 2, 0, 0 }, { 0, 1, 0 } };
  f.segments = { { 0, 1 }, { 1, 0 }, { 0, 4 }, { 2, 3 }, { 3, 5 } };
  EXPECT_THROW(f.validate(ballOracle(), 0), InputError); // as given: overlapping
  const FeatureMergeCounts counts = mergeFeatureSegments(f);
  EXPECT_TRUE(counts.changed());
  EXPECT_EQ(counts.mergedPoints, 1u);
  EXPECT_EQ(counts.duplicates, 2u);
  EXPECT_EQ(counts.overlapGroups, 1u);
  // the union (-2..3 on the x axis) plus the untouched segment to (0,1,0)
  EXPECT_NEAR(totalLength(f), 5.0 + std::sqrt(9.0 + 1.0), 1e-12);
  EXPECT_NO_THROW(f.validate(ballOracle(), 0));
  for (const auto& s : f.segments)
    EXPECT_NE(s[0], s[1]);
}

TEST(FeatureMerge, CleanLinesAndCrossingsAreLeftAsTheyAre)
{
  FeatureSegments clean;
  clean.points = { { 0, 0, 0 }, { 1, 0, 0 }, { 1, 1, 0 } };
  clean.segments = { { 0, 1 }, { 1, 2 } };
  const FeatureSegments before = clean;
  EXPECT_FALSE(mergeFeatureSegments(clean).changed());
  EXPECT_EQ(clean.segments, before.segments);

  FeatureSegments crossing; // an X: not an overlap, still refused by validate
  crossing.points = { { -1, 0, 0 }, { 1, 0, 0 }, { 0, -1, 0 }, { 0, 1, 0 } };
  crossing.segments = { { 0, 1 }, { 2, 3 } };
  EXPECT_FALSE(mergeFeatureSegments(crossing).changed());
  EXPECT_THROW(crossing.validate(ballOracle(), 0), InputError);
}

TEST(FeatureMerge, AbsurdCoordinatesAreRefusedByValidate)
{
  FeatureSegments f;
  f.points = { { 0, 0, 0 }, { 1e20, 0, 0 } };
  f.segments = { { 0, 1 } };
  try
  {
    f.validate(ballOracle(), 0);
    FAIL() << "accepted a coordinate of 1e20";
  }
  catch (const InputError& e)
  {
    EXPECT_NE(std::string(e.what()).find("1e15"), std::string::npos) << e.what();
  }
}

namespace
{
bool warnsOfContradiction(const std::vector<std::string>& warnings)
{
  for (const std::string& w : warnings)
    if (w.find("criteria contradict the feature lines") != std::string::npos)
      return true;
  return false;
}
}

// Paper section 5: B < 1/(2 sin alpha0) contradicts segments meeting at alpha0. A polyline bending
// by a few degrees at each vertex (a circle in 40 chords meets itself at 171 degrees) is no small
// angle; two segments at 20 degrees with B = 1.1 are (1/(2 sin 20) = 1.46).
TEST(FeatureSegmentsValidate, RadiusEdgeContradictionOnlyForSmallAngles)
{
  FeatureSegments circle;
  const int n = 40;
  for (int k = 0; k < n; ++k)
  {
    const double t = 2 * M_PI * k / n;
    circle.points.push_back({ 2 * std::cos(t), 2 * std::sin(t), 0 });
    circle.segments.push_back({ k, (k + 1) % n });
  }
  EXPECT_FALSE(warnsOfContradiction(circle.validate(ballOracle(), 1.1)));

  FeatureSegments wedge;
  const double a = 20 * M_PI / 180;
  wedge.points = { { 0, 0, 0 }, { 2, 0, 0 }, { 2 * std::cos(a), 2 * std::sin(a), 0 } };
  wedge.segments = { { 0, 1 }, { 0, 2 } };
  EXPECT_TRUE(warnsOfContradiction(wedge.validate(ballOracle(), 1.1)));
  EXPECT_FALSE(warnsOfContradiction(wedge.validate(ballOracle(), 1.5)));
}
