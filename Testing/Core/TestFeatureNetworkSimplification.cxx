// SPDX-License-Identifier: GPL-3.0-or-later
// simplifyFeatureNetwork (FeatureNetworkSimplification.h): noisy feature networks (nearly every
// point a branch point, small angles everywhere) made coarse, with the bounds it claims.
#include "FeatureNetworkSimplification.h"
#include "HierarchicalOracle.h"
#include "SphereDomain.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <random>
#include <set>
#include <string>

using namespace omesh;

namespace
{
/// Edges of a jittered triangular lattice (spacing `step` on [0,1]^2, a little out of plane),
/// about half of them kept at random: a network like the sharp edges of a noisy surface.
FeatureSegments noisyNetwork(double step, unsigned seed)
{
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> jitter(-0.2 * step, 0.2 * step);
  std::bernoulli_distribution keep(0.5);
  const int n = static_cast<int>(1.0 / step);
  FeatureSegments f;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i)
      f.points.push_back({ (i + 0.5 * (j % 2)) * step + jitter(random), j * step * 0.866 + jitter(random), jitter(random) });
  auto id = [&](int i, int j) { return j * (n + 1) + i; };
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i)
    {
      if (i < n && keep(random))
        f.segments.push_back({ id(i, j), id(i + 1, j) });
      if (j < n)
      {
        const int shift = j % 2; // odd rows sit half a step to the right
        if (keep(random))
          f.segments.push_back({ id(i, j), id(i, j + 1) });
        if (i + (shift ? 1 : -1) >= 0 && i + (shift ? 1 : -1) <= n && keep(random))
          f.segments.push_back({ id(i, j), id(i + (shift ? 1 : -1), j + 1) });
      }
    }
  return f;
}

bool isInputPoint(const FeatureSegments& input, const Vec3& p)
{
  return std::any_of(input.points.begin(), input.points.end(), [&](const Vec3& q) { return norm(p - q) == 0.0; });
}
}

// The claims of simplifyFeatureNetwork on a noisy network: kept points are input points, at least
// the merge distance apart and from every segment they do not end; angles at least asin(d / L)
// (L the longest segment); no crossing; the lines moved (both ways) within the stated bound, and
// the reported distances are the measured ones.
TEST(FeatureNetworkSimplification, NoisyNetworkBecomesCoarseWithinTheBound)
{
  const FeatureSegments input = noisyNetwork(0.02, 5);
  FeatureSegments f = input;
  FeatureNetworkTolerances tol;
  tol.edgeLength = 0.1;
  tol.chordTolerance = 0.01;
  const FeatureNetworkReport r = simplifyFeatureNetwork(f, tol);
  const double d = tol.mergeDistance();
  ASSERT_FALSE(f.empty());
  EXPECT_LT(f.segments.size(), input.segments.size() / 2);
  EXPECT_GE(r.shortestSegment, d); // kept points are at least d apart
  EXPECT_GT(r.pointsMerged, 0u);
  double longest = 0.0;
  for (size_t s = 0; s < f.segments.size(); ++s)
    longest = std::max(longest, f.length(s));
  for (size_t i = 0; i < f.points.size(); ++i)
  {
    EXPECT_TRUE(isInputPoint(input, f.points[i]));
    for (size_t j = i + 1; j < f.points.size(); ++j)
      EXPECT_GE(norm(f.points[i] - f.points[j]), d);
    // closer than d to a segment only as a neighbour of one of its ends, at 45 degrees or more there
    for (const auto& s : f.segments)
      if (s[0] != static_cast<int>(i) && s[1] != static_cast<int>(i) &&
        distanceToSegment(f.points[i], f.points[s[0]], f.points[s[1]]) < d)
      {
        bool wide = false;
        for (const auto& t : f.segments)
          for (int end : { 0, 1 })
            if (t[1 - end] == static_cast<int>(i) && (t[end] == s[0] || t[end] == s[1]))
              wide = wide || angleAt(f.points[t[end]], f.points[i], f.points[t[end] == s[0] ? s[1] : s[0]]) >= 45.0;
        EXPECT_TRUE(wide) << "point " << i << " lies closer than " << d << " to a segment";
      }
  }
  EXPECT_GE(f.smallestAngle(), tol.minAngle);
  EXPECT_DOUBLE_EQ(r.smallestAngle, f.smallestAngle());
  HierarchicalOracle o;
  o.add(std::make_shared<SphereDomain>(Vec3{ 0.5, 0.5, 0 }, 2.0, 1));
  EXPECT_NO_THROW(f.validate(o, 3.0)); // throws on crossings and zero-length segments
  const double bound = 9 * d + tol.chordTolerance + tol.spurLength();
  EXPECT_LE(r.simplifiedToGiven, bound);
  EXPECT_LE(r.givenToSimplified, bound);
  EXPECT_NEAR(r.simplifiedToGiven, featureLinesDistance(f, input, 0.002), 0.002);
  // measured without the given lines' separate pieces shorter than the spur length
  EXPECT_LE(r.givenToSimplified, featureLinesDistance(input, f, 0.002) + 0.002);
  EXPECT_GT(r.givenToSimplified, 0.0);
}

// Whiskers: a dangling chain shorter than the spur length goes, a long one stays; a separate short
// piece and a short loop go; a star made only of short spurs keeps its longest.
TEST(FeatureNetworkSimplification, ShortSpursAndPiecesDropped)
{
  FeatureSegments f;
  // a long line along x (0..1 in 10 steps) with a short whisker (0.05) and a long branch (0.5) at x = 0.5
  for (int i = 0; i <= 10; ++i)
    f.points.push_back({ 0.1 * i, 0, 0 });
  for (int i = 0; i < 10; ++i)
    f.segments.push_back({ i, i + 1 });
  f.points.push_back({ 0.5, 0.05, 0 });  // 11: whisker end
  f.segments.push_back({ 5, 11 });
  f.points.push_back({ 0.5, 0, -0.25 }); // 12, 13: long branch
  f.points.push_back({ 0.5, 0, -0.5 });
  f.segments.push_back({ 5, 12 });
  f.segments.push_back({ 12, 13 });
  // a separate short piece and a short triangle far away
  f.points.push_back({ 5, 5, 5 });
  f.points.push_back({ 5.06, 5, 5 });
  f.segments.push_back({ 14, 15 });
  f.points.push_back({ -5, 0, 0 });
  f.points.push_back({ -5.02, 0, 0 });
  f.points.push_back({ -5, 0.02, 0 });
  f.segments.push_back({ 16, 17 });
  f.segments.push_back({ 17, 18 });
  f.segments.push_back({ 18, 16 });
  FeatureNetworkTolerances tol;
  tol.edgeLength = 0.1;
  tol.chordTolerance = 0.001;
  tol.mergeFraction = 0.01; // nothing to merge here
  const FeatureNetworkReport r = simplifyFeatureNetwork(f, tol);
  EXPECT_EQ(r.spursDropped, 1u);
  EXPECT_EQ(r.piecesDropped, 2u);
  EXPECT_FALSE(isInputPoint(f, { 0.5, 0.05, 0 }));
  EXPECT_FALSE(isInputPoint(f, { 5, 5, 5 }));
  EXPECT_FALSE(isInputPoint(f, { -5, 0, 0 }));
  for (const Vec3& kept : { Vec3{ 0, 0, 0 }, Vec3{ 1, 0, 0 }, Vec3{ 0.5, 0, 0 }, Vec3{ 0.5, 0, -0.5 } })
    EXPECT_TRUE(isInputPoint(f, kept));

  // a star of three short spurs: the longest stays
  FeatureSegments star;
  star.points = { { 0, 0, 0 }, { 0.02, 0, 0 }, { 0, 0.03, 0 }, { 0, 0, -0.04 } };
  star.segments = { { 0, 1 }, { 0, 2 }, { 0, 3 } };
  simplifyFeatureNetwork(star, tol);
  ASSERT_EQ(star.segments.size(), 1u);
  EXPECT_TRUE(isInputPoint(star, { 0, 0, -0.04 }));
}

// Feature lines that are already coarse (a cube's edges at a fine edge size) stay as they are.
TEST(FeatureNetworkSimplification, CoarseNetworkLeftAlone)
{
  FeatureSegments f;
  for (int i = 0; i < 8; ++i)
    f.points.push_back({ double(i & 1), double((i >> 1) & 1), double((i >> 2) & 1) });
  for (int i = 0; i < 8; ++i)
    for (int b = 1; b < 8; b <<= 1)
      if (!(i & b))
        f.segments.push_back({ i, i | b });
  FeatureSegments g = f;
  FeatureNetworkTolerances tol;
  tol.edgeLength = 0.2;
  tol.chordTolerance = 0.01;
  const FeatureNetworkReport r = simplifyFeatureNetwork(g, tol);
  EXPECT_EQ(r.pointsMerged + r.pointsSnapped + r.spursDropped + r.piecesDropped, 0u);
  EXPECT_EQ(g.segments.size(), f.segments.size());
  EXPECT_EQ(r.givenToSimplified, 0.0);
  EXPECT_EQ(r.simplifiedToGiven, 0.0);
}

// With a domain: a chord that leaves it (it could be no mesh edge) is dropped, the lines inside stay.
TEST(FeatureNetworkSimplification, SegmentsLeavingTheDomainDropped)
{
  FeatureSegments f;
  // an inside line along x at y = 0 and a segment from it that pokes out of the unit ball
  for (int i = 0; i <= 8; ++i)
    f.points.push_back({ -0.8 + 0.2 * i, 0, 0 });
  for (int i = 0; i < 8; ++i)
    f.segments.push_back({ i, i + 1 });
  f.points.push_back({ 0.0, 0.99, 0.5 }); // 9: outside the ball (|p| > 1), joined to the middle point
  f.segments.push_back({ 4, 9 });
  FeatureNetworkTolerances tol;
  tol.edgeLength = 0.25;
  tol.chordTolerance = 0.01;
  tol.mergeFraction = 0.5; // the line's points (0.2 apart) stay
  tol.inDomain = [](const Vec3& p) { return norm(p) < 1.0; };
  const FeatureNetworkReport r = simplifyFeatureNetwork(f, tol);
  EXPECT_EQ(r.segmentsOutside, 1u);
  for (size_t s = 0; s < f.segments.size(); ++s)
    for (double t : { 0.25, 0.5, 0.75 })
      EXPECT_LT(norm(lerp(f.points[f.segments[s][0]], f.points[f.segments[s][1]], t)), 1.0);
  EXPECT_TRUE(isInputPoint(f, { -0.8, 0, 0 }));
  EXPECT_TRUE(isInputPoint(f, { 0.8, 0, 0 }));
  EXPECT_FALSE(isInputPoint(f, { 0.0, 0.99, 0.5 }));
}

// A line over the tip of a thin fin (a noise spike's ridge): the mesh has no room for cells beside
// its two segments at the tip (none in the fin's plane, nothing either side of it), so their first
// pieces could never be mesh edges; the tip is bypassed by its neighbours' chord, which stays in the
// domain. The same line over a thick fin keeps its tip.
TEST(FeatureNetworkSimplification, SegmentsOverAThinFinsTipBypassed)
{
  for (const double halfWidth : { 0.002, 0.2 })
  {
    FeatureSegments f;
    f.points = { { -0.5, 0, -0.1 }, { 0, 0, 0.9 }, { 0.5, 0, -0.1 } }; // up the fin's ridge and down
    f.segments = { { 0, 1 }, { 1, 2 } };
    FeatureNetworkTolerances tol;
    tol.edgeLength = 0.5;
    tol.chordTolerance = 0.001;  // resampling keeps the tip
    tol.mergeFraction = 0.01;    // nothing to merge
    tol.inDomain = [halfWidth](const Vec3& p) {
      return p.z < 0 || (std::abs(p.y) < halfWidth && p.z < 1 - std::abs(p.x)); // slab plus fin
    };
    const FeatureNetworkReport r = simplifyFeatureNetwork(f, tol);
    const bool thin = halfWidth < 0.01;
    EXPECT_EQ(r.unmeshableEnds, thin ? 1u : 0u) << "fin half width " << halfWidth;
    EXPECT_EQ(isInputPoint(f, { 0, 0, 0.9 }), !thin);
    EXPECT_EQ(f.segments.size(), thin ? 1u : 2u);
    EXPECT_TRUE(isInputPoint(f, { -0.5, 0, -0.1 }) && isInputPoint(f, { 0.5, 0, -0.1 }));
    if (thin) // the tip is 1 from the chord
      EXPECT_NEAR(r.givenToSimplified, 1.0, 0.02);
  }

  // a lone line end on the thin fin's tip has no room either: that segment goes
  FeatureSegments lone;
  lone.points = { { -1.0, 0, -0.1 }, { -0.5, 0, -0.1 }, { 0, 0, 0.9 } };
  lone.segments = { { 0, 1 }, { 1, 2 } };
  FeatureNetworkTolerances tol;
  tol.edgeLength = 0.5;
  tol.chordTolerance = 0.001;
  tol.mergeFraction = 0.01;
  tol.spurFraction = 0.01;
  tol.inDomain = [](const Vec3& p) { return p.z < 0 || (std::abs(p.y) < 0.002 && p.z < 1 - std::abs(p.x)); };
  const FeatureNetworkReport r = simplifyFeatureNetwork(lone, tol);
  EXPECT_EQ(r.unmeshableEnds, 1u);
  EXPECT_FALSE(isInputPoint(lone, { 0, 0, 0.9 }));
  EXPECT_TRUE(isInputPoint(lone, { -1.0, 0, -0.1 }) && isInputPoint(lone, { -0.5, 0, -0.1 }));
}

// A CAD part's convex corner whose solid wedge the plane of its two feature segments halves (a
// 90-degree ridge that turns down by 63 degrees, as where the generated implants' stem edges meet
// their chamfered tips): no room straight off that plane at the probe radius, but at 30 degrees
// from it, so the corner stays. Bypassed, the chord ran up to 0.9 mm inside the implant at a
// 4-degree angle to its crease, and refinement at radius-edge 1.1 piled vertices into that sliver
// of space until the vertex budget.
TEST(FeatureNetworkSimplification, ConvexCornerOfAWedgeKept)
{
  FeatureSegments f;
  f.points = { { -1, 0, 0 }, { 0, 0, 0 }, { 0.5, 0, -1 } }; // along the ridge, then down its turn
  f.segments = { { 0, 1 }, { 1, 2 } };
  FeatureNetworkTolerances tol;
  tol.edgeLength = 0.5;
  tol.chordTolerance = 0.001;
  tol.mergeFraction = 0.01;
  tol.inDomain = [](const Vec3& p) { return p.z + std::abs(p.y) < std::min(0.0, -2.0 * p.x); };
  const FeatureNetworkReport r = simplifyFeatureNetwork(f, tol);
  EXPECT_EQ(r.unmeshableEnds, 0u);
  EXPECT_TRUE(isInputPoint(f, { 0, 0, 0 }));
  EXPECT_EQ(f.segments.size(), 2u);
  EXPECT_NEAR(r.givenToSimplified, 0.0, 1e-9);
}

namespace
{
/// Two lines 0.2 apart along x: A (segments 0..11, own edge size 0.1) zigzags between 0.2 and
/// 0.45 above B (0.5 apart in x, chords of 1 replace two of them), B (segments 12..35, own edge
/// size 0.4) is straight on the x axis, 0.25 apart.
FeatureSegments zigzagBesideStraightLine()
{
  FeatureSegments f;
  for (int i = 0; i <= 12; ++i)
    f.points.push_back({ 0.5 * i, i % 2 ? 0.45 : 0.2, 0.0 });
  for (int i = 0; i < 12; ++i)
    f.segments.push_back({ i, i + 1 });
  for (int i = 0; i <= 24; ++i)
    f.points.push_back({ 0.25 * i, 0.0, 0.0 });
  for (int i = 0; i < 24; ++i)
    f.segments.push_back({ 13 + i, 14 + i });
  f.edgeSizes.assign(12, 0.1);
  f.edgeSizes.resize(36, 0.4);
  return f;
}
}

// A chord replacing A's zigzag runs 0.2 from B and 0.22 from A's own segments, so the segment
// nearest its midpoint is B's (checked below: the rule of before, transferEdgeSizes, gives it B's
// edge size). Its source says where it came from: a segment of A it covers, and A's edge size.
TEST(FeatureNetworkSimplification, ChordsKeepTheLineTheyCameFromWhereAnotherLineIsNearer)
{
  const FeatureSegments input = zigzagBesideStraightLine();
  FeatureSegments f = input;
  FeatureNetworkTolerances tol;
  tol.edgeLength = 1.0;
  tol.chordTolerance = 0.3;
  tol.mergeFraction = 0.1; // no merges or snaps: the lines are 0.2 apart
  simplifyFeatureNetwork(f, tol);
  ASSERT_EQ(f.source.size(), f.segments.size());
  ASSERT_EQ(f.edgeSizes.size(), f.segments.size());
  EXPECT_LT(f.segments.size(), input.segments.size()); // chords replaced the input segments
  const auto lineOf = [](const Vec3& p) { return p.y > 0.1 ? 'A' : 'B'; };
  const auto lineOfSegment = [](size_t s) { return s < 12 ? 'A' : 'B'; };
  for (size_t s = 0; s < f.segments.size(); ++s)
  {
    const Vec3 &a = f.points[f.segments[s][0]], &b = f.points[f.segments[s][1]];
    const char line = lineOf(a);
    ASSERT_EQ(lineOf(b), line);
    SCOPED_TRACE(std::string("chord of ") + line + " from x = " + std::to_string(a.x) + " to " + std::to_string(b.x));
    ASSERT_GE(f.source[s], 0);
    ASSERT_LT(f.source[s], static_cast<int>(input.segments.size()));
    const auto& from = input.segments[f.source[s]];
    EXPECT_EQ(lineOfSegment(static_cast<size_t>(f.source[s])), line);
    // the source is one of the segments the chord replaced (it lies within the chord's span)
    const double lo = std::min(a.x, b.x), hi = std::max(a.x, b.x);
    for (int e : from)
    {
      EXPECT_GE(input.points[e].x, lo);
      EXPECT_LE(input.points[e].x, hi);
    }
    EXPECT_EQ(f.edgeSizes[s], std::optional<double>(line == 'A' ? 0.1 : 0.4));
  }
  // The case tells the rules apart: by the nearest segment, some chord of A gets B's edge size.
  FeatureSegments nearest = f;
  transferEdgeSizes(input, nearest, std::numeric_limits<double>::infinity());
  size_t wrong = 0;
  for (size_t s = 0; s < f.segments.size(); ++s)
    wrong += nearest.edgeSizes[s] != f.edgeSizes[s];
  EXPECT_GT(wrong, 0u);
}

// Two segments made one by merging points: the one kept is the segment that stayed in place (A's
// points are kept, the lower indices on a tie of degrees), whichever was listed first.
TEST(FeatureNetworkSimplification, ASegmentMergedOntoAnotherIsTheOneThatStayed)
{
  FeatureSegments f;
  f.points = { { 0, 0.05, 0 }, { 1, 0.05, 0 }, { 0, 0, 0 }, { 1, 0, 0 } };
  f.segments = { { 2, 3 }, { 0, 1 } }; // B, then A
  f.edgeSizes = { 0.4, 0.1 };
  FeatureNetworkTolerances tol;
  tol.edgeLength = 1.0;
  tol.chordTolerance = 0.01;
  tol.mergeFraction = 0.1;
  tol.spurFraction = 0.5;
  const FeatureNetworkReport r = simplifyFeatureNetwork(f, tol);
  EXPECT_EQ(r.pointsMerged, 2u);
  ASSERT_EQ(f.segments.size(), 1u);
  EXPECT_EQ(f.points[f.segments[0][0]].y, 0.05);
  EXPECT_EQ(f.source, std::vector<int>{ 1 });
  EXPECT_EQ(f.edgeSizes, (std::vector<std::optional<double>>{ 0.1 }));
}

// Own edge sizes ride on the sources: they change no step of the simplification (they used to be
// carried beside the segments without being kept in step, so after a merge had collapsed a segment
// mergeFeatureSegments left the copies it should have merged).
TEST(FeatureNetworkSimplification, OwnEdgeSizesDoNotChangeTheLines)
{
  const FeatureSegments bare = noisyNetwork(0.02, 5);
  FeatureSegments sized = bare;
  sized.edgeSizes.assign(sized.segments.size(), 0.1);
  FeatureSegments f = bare;
  FeatureNetworkTolerances tol;
  tol.edgeLength = 0.1;
  tol.chordTolerance = 0.01;
  simplifyFeatureNetwork(f, tol);
  simplifyFeatureNetwork(sized, tol);
  EXPECT_EQ(sized.segments, f.segments);
  EXPECT_EQ(sized.source, f.source);
  ASSERT_EQ(sized.points.size(), f.points.size());
  for (size_t i = 0; i < f.points.size(); ++i)
    EXPECT_EQ(norm(sized.points[i] - f.points[i]), 0.0);
  EXPECT_EQ(sized.edgeSizes, std::vector<std::optional<double>>(f.segments.size(), 0.1));
}
