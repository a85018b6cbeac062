// SPDX-License-Identifier: GPL-3.0-or-later
// Rule T1 on the segments alone (SegmentConformation.h): the claims of T1.1, T1.2 and the
// concentric shells of small-angle clusters, checked on the segment set itself.
#include "SegmentConformation.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

using namespace omesh;

namespace
{
/// `n` segments from one apex, `angle` degrees apart in one plane, of the given lengths.
FeatureSegments fan(int n, double angle, const std::vector<double>& lengths)
{
  FeatureSegments f;
  const Vec3 apex{ 0.1, -0.2, 0.3 };
  f.points.push_back(apex);
  for (int i = 0; i < n; ++i)
  {
    const double a = i * angle * M_PI / 180.0;
    f.points.push_back(apex + lengths[i % lengths.size()] * Vec3{ std::cos(a), std::sin(a), 0.0 });
    f.segments.push_back({ 0, i + 1 });
  }
  return f;
}

/// Sub-segments whose diametral ball holds a segment point other than their ends.
size_t encroached(const SegmentSet& s)
{
  size_t n = 0;
  for (size_t i = 0; i < s.subs.size(); ++i)
  {
    const Vec3 a = s.points[s.subs[i][0]], b = s.points[s.subs[i][1]], mid = 0.5 * (a + b);
    const double r2 = 0.25 * dot(b - a, b - a);
    for (size_t p = 0; p < s.points.size(); ++p)
      if (static_cast<int>(p) != s.subs[i][0] && static_cast<int>(p) != s.subs[i][1] &&
        dot(s.points[p] - mid, s.points[p] - mid) < r2 * (1 - 1e-12))
      {
        ++n;
        break;
      }
  }
  return n;
}
}

// T1.2's claim: after conformation no sub-segment is encroached by a segment point, and none is
// longer than the edge size. Down to 1 degree the splitting ends without the point budget.
TEST(SegmentConformation, NoSubSegmentIsEncroachedOrTooLong)
{
  for (double angle : { 30.0, 5.0, 1.0 })
  {
    SCOPED_TRACE(angle);
    std::vector<std::string> warnings;
    const SegmentSet s = conformSegments(fan(4, angle, { 1.0, 0.6, 0.85, 0.3 }), 0.2, 100000, warnings);
    EXPECT_TRUE(warnings.empty());
    EXPECT_EQ(encroached(s), 0u);
    for (size_t i = 0; i < s.subs.size(); ++i)
      EXPECT_LE(s.length(i), 0.2 * (1 + 1e-12));
    EXPECT_LT(s.points.size(), 2000u);
  }
}

// Concentric shells: within the part of each segment next to the apex, the segments of a
// small-angle cluster carry their points at the same distances from the apex (up to the 1e-9
// tie-break); a segment at a wide angle is no member and keeps its own points.
TEST(SegmentConformation, SmallAngleClustersShareTheirShells)
{
  FeatureSegments f = fan(3, 2.0, { 1.0, 0.7, 0.9 });
  f.points.push_back(f.points[0] + Vec3{ 0.0, -0.8, 0.0 }); // 90 degrees from the fan
  f.segments.push_back({ 0, 4 });
  std::vector<std::string> warnings;
  const SegmentSet s = conformSegments(f, 0.05, 100000, warnings);
  EXPECT_GT(s.mirrored, 0u);
  auto distances = [&](int input, double within) {
    std::vector<double> d;
    for (size_t p = 0; p < s.points.size(); ++p)
      for (const auto& sub : s.subs)
        if (sub[2] == input && (sub[0] == static_cast<int>(p) || sub[1] == static_cast<int>(p)))
        {
          const double r = norm(s.points[p] - f.points[0]);
          if (r > 0 && r <= within)
            d.push_back(r);
          break;
        }
    std::sort(d.begin(), d.end());
    return d;
  };
  // within the shortest member's half, away from its middle (where its other end's splits, which
  // are not mirrored, take over)
  const double half = 0.8 * 0.5 * 0.7;
  const std::vector<double> shells = distances(0, half);
  ASSERT_GT(shells.size(), 2u);
  for (int input : { 1, 2 })
  {
    const std::vector<double> other = distances(input, half);
    ASSERT_EQ(other.size(), shells.size()) << "segment " << input;
    for (size_t i = 0; i < shells.size(); ++i)
      EXPECT_NEAR(other[i], shells[i], 1e-8 * shells[i]) << "segment " << input;
  }
  EXPECT_NE(distances(3, 0.4), distances(0, 0.4)); // the wide one is on its own
}

// T1.1 below a right angle only: a polyline sampling an arc keeps its chords whole (no segment
// point can lie in a neighbour's diametral ball across an angle of 90 degrees or more), while the
// apex of a 60-degree corner and the two segments of a three-segment vertex that meet below 90
// degrees are still trimmed; nothing is left encroached. (The paper's rule trims every vertex that ends
// two segments: each chord in three.)
TEST(SegmentConformation, ChainVerticesAtRightAnglesOrMoreAreNotTrimmed)
{
  FeatureSegments f;
  const int arc = 12; // points 0..12 on a circle of radius 2, 10 degrees apart
  for (int k = 0; k <= arc; ++k)
    f.points.push_back(2.0 * Vec3{ std::cos(k * M_PI / 18), std::sin(k * M_PI / 18), 0.0 });
  for (int k = 0; k < arc; ++k)
    f.segments.push_back({ k, k + 1 });
  const Vec3 end = f.points[arc];
  const Vec3 back = (1.0 / norm(f.points[arc - 1] - end)) * (f.points[arc - 1] - end);
  const double c60 = 0.5, s60 = std::sqrt(3.0) / 2; // 13: a corner of 60 degrees, back turned about z
  f.points.push_back(end + 0.5 * Vec3{ c60 * back.x - s60 * back.y, s60 * back.x + c60 * back.y, 0.0 });
  f.segments.push_back({ arc, arc + 1 });
  f.points.push_back(f.points[0] + Vec3{ 0.0, -0.4, 0.0 }); // 14 and 15: three segments at point 0
  f.points.push_back(f.points[0] + Vec3{ 0.3, -0.3, 0.3 }); // 55 degrees from 14, over 90 from the arc
  f.segments.push_back({ 0, 14 });
  f.segments.push_back({ 0, 15 });
  std::vector<bool> trimmed(f.points.size(), false); // a vertex where some segment end is trimmed
  const std::vector<std::array<bool, 2>> ends = f.endsBelowRightAngle();
  for (size_t s = 0; s < f.segments.size(); ++s)
    for (int side : { 0, 1 })
      if (ends[s][side])
        trimmed[f.segments[s][side]] = true;
  const double cornerAngle = angleAt(f.points[arc], f.points[arc - 1], f.points[arc + 1]);
  ASSERT_LT(cornerAngle, 90.0);
  EXPECT_TRUE(trimmed[0]);
  EXPECT_TRUE(trimmed[arc]);
  for (int k = 1; k < arc; ++k)
    EXPECT_FALSE(trimmed[k]) << k;

  std::vector<std::string> warnings;
  const SegmentSet below = conformSegments(f, std::vector<double>(f.segments.size(), 0.0), 100000, warnings);
  EXPECT_EQ(encroached(below), 0u);
  auto piecesOf = [](const SegmentSet& s, int input) {
    return std::count_if(s.subs.begin(), s.subs.end(), [&](const auto& sub) { return sub[2] == input; });
  };
  for (int k = 2; k < arc - 1; ++k) // chords between two chain vertices: whole
    EXPECT_EQ(piecesOf(below, k), 1) << k;
  // at the 60-degree corner and at the vertex of three segments: trimmed at l_min / 3
  EXPECT_GT(piecesOf(below, arc), 1);
  EXPECT_GT(piecesOf(below, arc + 1), 1);
  EXPECT_GT(piecesOf(below, arc + 2), 1);
}

// T1.1 at a junction: a segment leaving at 90 degrees or more from every other segment there is
// not trimmed, and its length does not set the others' trims (the paper's l_min is the shortest
// segment at the vertex: a short curve leaving a junction of found lines cut every other curve
// there into short pieces, and the mesh graded down to them). Two segments at 60 degrees (lengths
// 1 and 1.2) and a short one (0.15) leaving at 150 degrees from both: the two are trimmed at 1/3,
// the short one stays whole, nothing is left encroached.
TEST(SegmentConformation, ASegmentAtRightAnglesOrMoreToEveryOtherAtAJunctionIsNotTrimmedNorSetsTheTrims)
{
  FeatureSegments f;
  auto at = [](double degrees, double length) {
    const double r = degrees * M_PI / 180;
    return length * Vec3{ std::cos(r), std::sin(r), 0.0 };
  };
  f.points = { Vec3{ 0, 0, 0 }, at(0, 1.0), at(60, 1.2), at(210, 0.15) };
  f.segments = { { 0, 1 }, { 0, 2 }, { 0, 3 } };
  std::vector<std::string> warnings;
  const SegmentSet set = conformSegments(f, std::vector<double>(f.segments.size(), 0.0), 100000, warnings);
  EXPECT_EQ(encroached(set), 0u);
  auto shortestAtApex = [&](int input) {
    double shortest = std::numeric_limits<double>::infinity();
    int pieces = 0;
    for (const auto& sub : set.subs)
      if (sub[2] == input)
      {
        ++pieces;
        if (sub[0] == 0 || sub[1] == 0)
          shortest = std::min(shortest, norm(set.points[sub[1]] - set.points[sub[0]]));
      }
    return std::make_pair(pieces, shortest);
  };
  EXPECT_EQ(shortestAtApex(2).first, 1) << "the segment at 150 degrees from both others stays whole";
  for (int input : { 0, 1 })
    EXPECT_NEAR(shortestAtApex(input).second, 1.0 / 3.0, 1e-6) << "trimmed at l_min / 3 of the two, segment " << input;
}
