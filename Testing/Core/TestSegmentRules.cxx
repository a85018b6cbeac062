// SPDX-License-Identifier: GPL-3.0-or-later
// The paper's rules on constrained segments (SegmentRules.h), each checked against its claim in
// section 2 of the paper.
#include "SegmentRules.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace omesh;

// Section 2.1: p encroaches ab iff ||p - m|| < ||a - m||: the open diametral ball, not its sphere.
TEST(SegmentRules, EncroachmentIsTheOpenDiametralBall)
{
  const Vec3 a{ 1, 2, 3 }, b{ 3, 2, 3 }; // midpoint (2, 2, 3), radius 1
  EXPECT_TRUE(rules::encroaches(a, b, { 2, 2, 3 }));
  EXPECT_TRUE(rules::encroaches(a, b, { 2, 2.99, 3 }));
  EXPECT_TRUE(rules::encroaches(a, b, { 1.2, 2, 3.1 }));
  EXPECT_FALSE(rules::encroaches(a, b, { 2, 3, 3 }));  // on the sphere
  EXPECT_FALSE(rules::encroaches(a, b, a));            // the ends lie on the sphere
  EXPECT_FALSE(rules::encroaches(a, b, b));
  EXPECT_FALSE(rules::encroaches(a, b, { 2, 2, 4.5 })); // outside
  EXPECT_FALSE(rules::encroaches(a, b, { 0.9, 2, 3 })); // beyond an end, on the line
}

// T1.1: a segment at a star vertex longer than l_min / 3 gets the point at distance l_min / 3 from
// the star vertex; a segment not longer keeps its length.
TEST(SegmentRules, T11TrimsAtAThirdOfTheShortestSegmentAtTheStarVertex)
{
  const double lmin = 0.9, cut = lmin / 3.0;
  for (double length : { 0.9, 2.0, 17.5 })
  {
    const std::optional<double> t = rules::trimAtStarVertexT11(length, cut);
    ASSERT_TRUE(t.has_value()) << length;
    EXPECT_NEAR(*t * length, cut, 1e-12 * length);
    EXPECT_GT(*t, 0.0);
    EXPECT_LT(*t, 1.0);
  }
  EXPECT_FALSE(rules::trimAtStarVertexT11(cut, cut).has_value());
  EXPECT_FALSE(rules::trimAtStarVertexT11(0.5 * cut, cut).has_value());
  EXPECT_FALSE(rules::trimAtStarVertexT11(cut * (1 + 1e-12), cut).has_value()); // rounding of an equal length
}

// T1.2: an encroached segment (or one longer than the edge size) is split at its midpoint; a free
// one is left alone, and so is an encroached one whose halves would fall below the floor.
TEST(SegmentRules, T12SplitsEncroachedSegmentsAtTheirMidpoint)
{
  const Vec3 a{ 0, 0, 0 }, b{ 2, 0, 0 };
  EXPECT_EQ(rules::splitEncroachedT12(a, b, true, 0.0, 0.1), std::optional<double>(0.5));
  EXPECT_FALSE(rules::splitEncroachedT12(a, b, false, 0.0, 0.1).has_value());
  EXPECT_FALSE(rules::splitEncroachedT12(a, b, false, 2.0, 0.1).has_value()); // exactly the edge size
  EXPECT_EQ(rules::splitEncroachedT12(a, b, false, 1.5, 0.1), std::optional<double>(0.5)); // too long
  EXPECT_FALSE(rules::splitEncroachedT12(a, b, true, 0.0, 1.01).has_value()); // half-length 1 < floor
  EXPECT_EQ(rules::splitEncroachedT12(a, b, true, 0.0, 1.0), std::optional<double>(0.5));
}

// T2.1 / T3.1: a refinement point inside a segment's diametral ball is never inserted; that
// segment is split instead (its midpoint is the ball's centre c'), or the point is given up when
// the segment cannot be split. Outside every ball the point is inserted (T2.2, T3.2-T3.4).
TEST(SegmentRules, T21T31RefinementPointsInADiametralBallSplitTheSegmentInstead)
{
  const std::vector<rules::NearSegment> near = {
    { { 0, 0, 0 }, { 1, 0, 0 }, true },
    { { 1, 0, 0 }, { 1, 2, 0 }, true },
    { { 5, 5, 5 }, { 5, 5, 6 }, false },
  };
  size_t which = 99;
  EXPECT_EQ(rules::refinementPointT21T31({ 0.5, 0.2, 0 }, near, &which), rules::RefinementPointFate::SplitSegment);
  EXPECT_EQ(which, 0u);
  EXPECT_EQ(rules::refinementPointT21T31({ 1.3, 1.0, 0.1 }, near, &which), rules::RefinementPointFate::SplitSegment);
  EXPECT_EQ(which, 1u);
  EXPECT_EQ(rules::refinementPointT21T31({ 5, 5, 5.5 }, near, &which), rules::RefinementPointFate::Drop);
  EXPECT_EQ(which, 2u);
  EXPECT_EQ(rules::refinementPointT21T31({ 3, 3, 3 }, near, nullptr), rules::RefinementPointFate::Insert);
  EXPECT_EQ(rules::refinementPointT21T31({ 0.5, -0.5, 0 }, near, nullptr), rules::RefinementPointFate::Insert); // on the sphere
  EXPECT_EQ(rules::refinementPointT21T31({ 0.5, 0.1, 0 }, {}, nullptr), rules::RefinementPointFate::Insert);
}
