// SPDX-License-Identifier: GPL-3.0-or-later
#include "SeamWelding.h"
#include "TestShapes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>
#include <set>

using namespace omesh;

namespace
{
/// A latitude-longitude sphere: near its poles the edges along a latitude are far shorter than
/// those along a meridian, the fans of many thin triangles an exporter writes.
TriangleSurface uvSphere(double r, int rings, int segments)
{
  TriangleSurface s;
  s.points.push_back({ 0, 0, r });
  for (int i = 1; i < rings; ++i)
    for (int j = 0; j < segments; ++j)
    {
      const double theta = M_PI * i / rings, phi = 2 * M_PI * j / segments;
      s.points.push_back({ r * std::sin(theta) * std::cos(phi), r * std::sin(theta) * std::sin(phi), r * std::cos(theta) });
    }
  s.points.push_back({ 0, 0, -r });
  const int south = static_cast<int>(s.points.size()) - 1;
  auto at = [&](int i, int j) { return 1 + (i - 1) * segments + (j % segments); };
  for (int j = 0; j < segments; ++j)
  {
    s.triangles.push_back({ 0, at(1, j), at(1, j + 1) });
    for (int i = 1; i + 1 < rings; ++i)
    {
      s.triangles.push_back({ at(i, j), at(i + 1, j), at(i + 1, j + 1) });
      s.triangles.push_back({ at(i, j), at(i + 1, j + 1), at(i, j + 1) });
    }
    s.triangles.push_back({ south, at(rings - 1, j + 1), at(rings - 1, j) });
  }
  return s;
}

/// Whether each point of the welded soup stands for copies of one point of `clean` only (soup
/// triangle t is clean triangle t, corner for corner, and weldSeams keeps the order).
bool mergesOnlyCopies(const TriangleSurface& clean, const SeamWelding& w)
{
  std::map<int, std::set<int>> origins;
  for (size_t t = 0; t < clean.triangles.size(); ++t)
    for (int k = 0; k < 3; ++k)
      origins[w.surface.triangles[t][k]].insert(clean.triangles[t][k]);
  for (const auto& [point, from] : origins)
    if (from.size() != 1)
      return false;
  return true;
}
}

TEST(SeamWelding, TheCopiesOfEachPointOfASoupBecomeOne)
{
  const TriangleSurface sphere = test::icosphere({ 0, 0, 0 }, 5.0, 3);
  const double jitter = 1e-4;
  const TriangleSurface soup = test::soupOf(sphere, jitter, 3);
  const SeamWelding w = weldSeams(soup, 1e-3 * 10.0 * std::sqrt(3.0));
  EXPECT_EQ(w.borderEdges, soup.triangles.size() * 3);
  EXPECT_EQ(w.pairedEdges, w.borderEdges);
  EXPECT_EQ(w.mergedPoints, soup.points.size() - sphere.points.size());
  EXPECT_EQ(w.surface.points.size(), sphere.points.size());
  EXPECT_TRUE(w.surface.borderEdges().empty());
  EXPECT_NO_THROW(w.surface.validateClosed("welded"));
  EXPECT_TRUE(mergesOnlyCopies(sphere, w));
  EXPECT_LE(w.largestMove, 2 * std::sqrt(3.0) * jitter);
  EXPECT_LE(w.widestGap, 2 * std::sqrt(3.0) * jitter);
  EXPECT_NEAR(w.surface.signedVolume(), sphere.signedVolume(), 1e-3 * sphere.signedVolume());
  const std::string edges = std::to_string(w.borderEdges);
  EXPECT_NE(w.describe().find("welded " + edges + " unwelded seam edge(s) (of " + edges + " border edges)"), std::string::npos)
    << w.describe();
}

TEST(SeamWelding, CopiesOfDifferentPointsAreNeverMerged)
{
  // at a latitude-longitude sphere's poles the jitter is as large as the short edges: seams there
  // are ambiguous and may stay open, but no point may be merged with a copy of another
  const TriangleSurface sphere = uvSphere(10.0, 60, 240);
  for (double jitter : { 1e-4, 1e-3, 4e-3 })
  {
    const TriangleSurface soup = test::soupOf(sphere, jitter, 7);
    const SeamWelding w = weldSeams(soup, 1e-3 * 20.0 * std::sqrt(3.0));
    EXPECT_TRUE(mergesOnlyCopies(sphere, w)) << jitter;
    EXPECT_NO_THROW(w.surface.validateTriangles("welded")) << jitter;
    EXPECT_GT(w.pairedEdges, w.borderEdges * 9 / 10) << jitter;
    EXPECT_LE(w.largestMove, 2 * w.widestGap) << jitter;
  }
}

TEST(SeamWelding, ClosedSurfacesAndSeamsWiderThanTheLimitAreLeftAlone)
{
  const TriangleSurface cube = test::cube(0, 1);
  const SeamWelding closed = weldSeams(cube, 1.0);
  EXPECT_FALSE(closed.welded());
  EXPECT_EQ(closed.borderEdges, 0u);
  EXPECT_EQ(closed.surface.points.size(), cube.points.size());
  // jitter 0.01 per coordinate, limit 0.005: only the few seams that happen to be narrower close
  const TriangleSurface soup = test::soupOf(test::icosphere({ 0, 0, 0 }, 5.0, 2), 0.01, 5);
  const SeamWelding wide = weldSeams(soup, 0.005);
  EXPECT_LT(wide.pairedEdges, wide.borderEdges / 10);
  EXPECT_LE(wide.widestGap, 0.005);
  EXPECT_LE(wide.largestMove, 0.005);
  EXPECT_EQ(wide.surface.points.size(), soup.points.size() - wide.mergedPoints);
  const SeamWelding none = weldSeams(soup, 1e-4);
  EXPECT_FALSE(none.welded());
  EXPECT_EQ(none.surface.triangles, soup.triangles);
}

TEST(SeamWelding, TinyEdgesFarFromTheOriginAreHandled)
{
  // edges 1e-300 long at 1e14 from the origin: their cells' indices would overflow a cast
  const TriangleSurface cube = test::cube(0, 1);
  TriangleSurface soup = test::soupOf(cube, 0.0, 1);
  const int first = static_cast<int>(soup.points.size());
  for (const Vec3& p : { Vec3{ 1e14, 1e14, 1e14 }, Vec3{ 1e14, 1e14, 1e14 + 1e-2 }, Vec3{ 1e14, 1e14 + 1e-2, 1e14 } })
    soup.points.push_back(p);
  soup.points.push_back({ 1e-300, 0, 0 });
  soup.points.push_back({ 0, 2e-300, 0 });
  soup.points.push_back({ 0, 0, 3e-300 });
  soup.triangles.push_back({ first, first + 1, first + 2 });
  soup.triangles.push_back({ first + 3, first + 4, first + 5 });
  const SeamWelding w = weldSeams(soup, 1.0);
  EXPECT_EQ(w.surface.triangles.size(), soup.triangles.size());
  EXPECT_EQ(w.surface.points.size() + w.mergedPoints, soup.points.size());
  EXPECT_NO_THROW(w.surface.validateTriangles("welded"));
}

TEST(SeamWelding, RandomSoupsGiveValidSurfaces)
{
  // random triangles over few points (shared edges, non-manifold fans, slivers, repeated points),
  // jittered copies: whatever is welded, the result is a valid surface whose points each stand
  // for input points within the limit
  std::mt19937 rng(31);
  for (int round = 0; round < 200; ++round)
  {
    const int points = 4 + static_cast<int>(rng() % 12);
    std::uniform_real_distribution<double> u(-1, 1), jitter(-1e-3, 1e-3);
    TriangleSurface base;
    for (int i = 0; i < points; ++i)
      base.points.push_back({ u(rng), u(rng), round % 3 == 0 ? 0.0 : u(rng) });
    for (int t = 0; t < 3 + static_cast<int>(rng() % 20); ++t)
    {
      int a = static_cast<int>(rng() % points), b = static_cast<int>(rng() % points), c = static_cast<int>(rng() % points);
      if (a != b && b != c && a != c)
        base.triangles.push_back({ a, b, c });
    }
    if (base.triangles.empty())
      continue;
    TriangleSurface soup = round % 2 ? test::soupOf(base, 0.0, 1) : base;
    for (Vec3& p : soup.points)
      p = p + Vec3{ jitter(rng), jitter(rng), jitter(rng) };
    const double limit = 0.01;
    const SeamWelding w = weldSeams(soup, limit);
    ASSERT_NO_THROW(w.surface.validateTriangles("welded")) << round;
    ASSERT_EQ(w.surface.triangles.size(), soup.triangles.size()) << round;
    ASSERT_EQ(w.pointIndex.size(), soup.points.size()) << round;
    for (size_t v = 0; v < soup.points.size(); ++v)
    {
      ASSERT_GE(w.pointIndex[v], 0);
      ASSERT_LT(w.pointIndex[v], static_cast<int>(w.surface.points.size()));
      EXPECT_LE(norm(w.surface.points[w.pointIndex[v]] - soup.points[v]), limit + 1e-12) << round;
    }
    for (size_t t = 0; t < soup.triangles.size(); ++t)
      for (int k = 0; k < 3; ++k)
        ASSERT_EQ(w.surface.triangles[t][k], w.pointIndex[soup.triangles[t][k]]) << round;
  }
}
