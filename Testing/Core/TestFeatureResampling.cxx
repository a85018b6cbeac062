// SPDX-License-Identifier: GPL-3.0-or-later
// resampleFeatureLines (FeatureSegments.h) and meshing with it: noisy feature lines made of many
// tiny segments, as sharp edges of scanned surfaces come.
#include "FeatureSegments.h"
#include "HierarchicalOracle.h"
#include "MeshQuality.h"
#include "OracleMesher.h"
#include "SphereDomain.h"

#include <gtest/gtest.h>

#include <string>

#include <algorithm>
#include <cmath>
#include <memory>
#include <random>

using namespace omesh;

namespace
{
/// A closed circle of `n` segments whose points wiggle radially by up to `noise` (fixed seed),
/// plus a straight tail of 5 segments leaving point 0 at a corner.
FeatureSegments noisyCircle(int n, double radius, double noise)
{
  std::mt19937 random(7);
  std::uniform_real_distribution<double> wiggle(-noise, noise);
  FeatureSegments f;
  for (int i = 0; i < n; ++i)
  {
    const double a = 2 * M_PI * i / n, r = radius + (i == 0 ? 0.0 : wiggle(random));
    f.points.push_back({ r * std::cos(a), r * std::sin(a), 0.1 * wiggle(random) });
    f.segments.push_back({ i, (i + 1) % n });
  }
  for (int k = 1; k <= 5; ++k)
  {
    f.points.push_back({ radius, 0.0, 0.08 * k });
    f.segments.push_back({ k == 1 ? 0 : n + k - 2, n + k - 1 });
  }
  return f;
}
}

// The claims: kept points are input points; every input point lies within the tolerance of the
// resampled lines; chords are at most the length bound (or one input segment); corners stay; the
// count drops to about length / bound.
TEST(FeatureResampling, ChordsWithinToleranceOfTheInputAndCornersKept)
{
  const FeatureSegments input = noisyCircle(3000, 0.5, 2e-4);
  FeatureSegments f = input;
  const double maxLength = 0.1, tolerance = 0.005;
  const size_t dropped = resampleFeatureLines(f, maxLength, tolerance);
  EXPECT_GT(dropped, 2500u);
  EXPECT_EQ(f.points.size() + dropped, input.points.size());
  EXPECT_LT(f.segments.size(), 2 * static_cast<size_t>(2 * M_PI * 0.5 / maxLength) + 10);
  for (const Vec3& p : f.points)
    EXPECT_NE(std::find_if(input.points.begin(), input.points.end(), [&](const Vec3& q) { return norm(p - q) == 0.0; }),
      input.points.end());
  for (const Vec3& p : input.points)
  {
    double nearest = 1e300;
    for (const auto& s : f.segments)
      nearest = std::min(nearest, distanceToSegment(p, f.points[s[0]], f.points[s[1]]));
    EXPECT_LE(nearest, tolerance * (1 + 1e-12));
  }
  for (size_t s = 0; s < f.segments.size(); ++s)
    EXPECT_LE(f.length(s), maxLength * (1 + 1e-12));
  // the corner where the tail leaves the circle, and the tail's end
  for (const Vec3& corner : { input.points[0], input.points.back() })
    EXPECT_NE(std::find_if(f.points.begin(), f.points.end(), [&](const Vec3& q) { return norm(corner - q) == 0.0; }),
      f.points.end());
  HierarchicalOracle o;
  o.add(std::make_shared<SphereDomain>(Vec3{ 0, 0, 0 }, 1.0, 1));
  EXPECT_NO_THROW(f.validate(o, 3.0)); // throws on crossing or zero-length segments
}

// The chords between two corners come as few as the greedy sleeve makes them, but of even length:
// a quarter circle sampled every 0.001 (arc 1.5708) and a straight tail of 1.03 at chords of at
// most 0.25 took 7 and 5 chords, the tail's last one 0.03 long (the greedy sleeve's remainder,
// which at a junction sets the trims of every line there); now each within 5 % of its chain's
// arc length / chord count, every point still within the tolerance.
TEST(FeatureResampling, ChordsBetweenCornersAreAsFewAsGreedyButEven)
{
  FeatureSegments f;
  const double r = 1.0, step = 0.001;
  const int arc = static_cast<int>(std::round(0.5 * M_PI * r / step));
  for (int k = 0; k <= arc; ++k)
    f.points.push_back({ r * std::cos(0.5 * M_PI * k / arc), r * std::sin(0.5 * M_PI * k / arc), 0.0 });
  for (int k = 1; k <= 1030; ++k) // the tail leaves the arc's end at a right angle: a corner
    f.points.push_back({ 0.0, r + step * k, 0.0 });
  for (size_t k = 0; k + 1 < f.points.size(); ++k)
    f.segments.push_back({ static_cast<int>(k), static_cast<int>(k + 1) });
  const FeatureSegments input = f;
  const double maxLength = 0.25, tolerance = 0.01;
  resampleFeatureLines(f, maxLength, tolerance);
  std::vector<double> onArc, onTail;
  for (size_t s = 0; s < f.segments.size(); ++s)
  {
    EXPECT_LE(f.length(s), maxLength * (1 + 1e-12));
    const Vec3 m = 0.5 * (f.points[f.segments[s][0]] + f.points[f.segments[s][1]]);
    (m.y < r ? onArc : onTail).push_back(f.length(s));
  }
  ASSERT_EQ(onArc.size(), 7u) << "as few chords as the greedy sleeve";
  ASSERT_EQ(onTail.size(), 5u);
  for (double l : onArc)
    EXPECT_NEAR(l, 2 * r * std::sin(0.25 * M_PI / 7), 0.05 * 0.5 * M_PI * r / 7);
  for (double l : onTail)
    EXPECT_NEAR(l, 1.03 / 5, 0.05 * 1.03 / 5);
  for (const Vec3& p : input.points)
  {
    double nearest = 1e300;
    for (const auto& s : f.segments)
      nearest = std::min(nearest, distanceToSegment(p, f.points[s[0]], f.points[s[1]]));
    EXPECT_LE(nearest, tolerance * (1 + 1e-12));
  }
}

// A line that is already coarse stays as it is.
TEST(FeatureResampling, CoarseLinesAreLeftAlone)
{
  FeatureSegments f;
  f.points = { { 0, 0, 0 }, { 1, 0, 0 }, { 1, 1, 0 }, { 1, 1, 1 } };
  f.segments = { { 0, 1 }, { 1, 2 }, { 2, 3 } };
  const FeatureSegments before = f;
  EXPECT_EQ(resampleFeatureLines(f, 0.5, 0.01), 0u);
  EXPECT_EQ(f.segments, before.segments);
}

// Meshing a noisy feature line: with resampling the Conforming strategy ends quickly with a valid
// mesh that keeps every resampled segment.
TEST(FeatureResampling, ConformingMeshesNoisyFeatureLinesWhenResampled)
{
  HierarchicalOracle o;
  o.add(std::make_shared<SphereDomain>(Vec3{ 0, 0, 0 }, 1.0, 1));
  const FeatureSegments noisy = noisyCircle(3000, 0.5, 2e-4);
  MesherOptions opt;
  opt.criteria.global.facetSize = opt.criteria.global.cellSize = 0.2;
  opt.criteria.global.facetDistance = 0.02;
  opt.criteria.global.edgeSize = 0.1;
  opt.resampleFeatureLines = true;
  opt.maximumNumberOfVertices = 200000;
  const TetMesh m = meshOracle(o, noisy, {}, opt);
  EXPECT_EQ(m.statistics.at("validity.defects"), 0.0);
  EXPECT_EQ(m.statistics.at("feature_segments_before_resampling"), static_cast<double>(noisy.segments.size()));
  EXPECT_NEAR(m.statistics.at("feature_coverage"), 1.0, 1e-12);
  EXPECT_LT(m.points.size(), 50000u);
}

// A line inside a ball and a spur that leaves it: the spur is dropped on purpose (no mesh edge can
// hold it), which is no movement. The warning says how far the lines kept lie from the given ones
// (here not at all) apart from how far the given ones lie from those kept (the spur's length), not
// one "moved by" figure of the larger (2.9 mm on a study case whose kept lines moved 0.44).
TEST(FeatureResampling, TheWarningTellsDroppedPiecesFromMovedLines)
{
  HierarchicalOracle o;
  o.add(std::make_shared<SphereDomain>(Vec3{ 0, 0, 0 }, 1.0, 1));
  FeatureSegments f;
  f.points = { { -0.5, 0, 0 }, { 0, 0, 0 }, { 0.5, 0, 0 }, { 0, 0, 1.6 } }; // the last one outside the ball
  f.segments = { { 0, 1 }, { 1, 2 }, { 1, 3 } };
  MesherOptions opt;
  opt.criteria.global.facetSize = opt.criteria.global.cellSize = 0.4;
  opt.criteria.global.facetDistance = 0.05;
  opt.criteria.global.edgeSize = 0.25;
  opt.resampleFeatureLines = true;
  const TetMesh m = meshOracle(o, f, {}, opt);
  EXPECT_EQ(m.statistics.at("feature_network.segments_outside_dropped"), 1.0);
  EXPECT_LT(m.statistics.at("feature_network.simplified_to_given"), 1e-9);
  EXPECT_NEAR(m.statistics.at("feature_network.given_to_simplified"), 1.6, 0.01);
  std::string warning;
  for (const auto& w : m.warnings)
    if (w.rfind("feature lines simplified", 0) == 0)
      warning = w;
  EXPECT_NE(warning.find("the lines kept lie within 0 of the given ones"), std::string::npos) << warning;
  EXPECT_NE(warning.find("the given ones within 1.6 of those kept (1 segment(s) outside the domain"), std::string::npos) << warning;
  EXPECT_NEAR(m.statistics.at("feature_coverage"), 1.0, 1e-12);
}
