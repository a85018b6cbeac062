// SPDX-License-Identifier: GPL-3.0-or-later
#include "InputError.h"
#include "SurfaceDomain.h"
#include "TestShapes.h"

#include <gtest/gtest.h>

#include <random>

using namespace omesh;

TEST(SurfaceDomain, CubeBoundaryPointsAreInsideAndNeighboursAreNot)
{
  SurfaceDomain cube(test::cube(0, 1), 7);
  EXPECT_NEAR(cube.volume(), 1.0, 1e-12);
  // every vertex, edge midpoint, face centre and face-diagonal point belongs to the closed solid
  for (int i = 0; i <= 4; ++i)
    for (int j = 0; j <= 4; ++j)
      for (int k = 0; k <= 4; ++k)
      {
        const Vec3 p{ i / 4.0, j / 4.0, k / 4.0 };
        const bool onBoundary = i == 0 || i == 4 || j == 0 || j == 4 || k == 0 || k == 4;
        EXPECT_EQ(cube.material(p), 7) << p.x << " " << p.y << " " << p.z << (onBoundary ? " (boundary)" : "");
      }
  // just outside every vertex and edge: the rays from these points graze edges and vertices
  const double e = 1e-9;
  for (int i = 0; i <= 2; ++i)
    for (int j = 0; j <= 2; ++j)
    {
      EXPECT_EQ(cube.material({ i / 2.0, j / 2.0, -e }), kOutside);
      EXPECT_EQ(cube.material({ i / 2.0, j / 2.0, 1 + e }), kOutside);
      EXPECT_EQ(cube.material({ -e, i / 2.0, j / 2.0 }), kOutside);
      EXPECT_EQ(cube.material({ i / 2.0, 1 + e, j / 2.0 }), kOutside);
      EXPECT_EQ(cube.material({ i / 2.0, j / 2.0, e }), 7);
    }
}

TEST(SurfaceDomain, NoLeaksAlongRaysThroughEdges)
{
  // Points on lines that run through the cube's triangle diagonals and edges, inside and outside:
  // a parity test that counts a grazed edge twice (or zero times) would flip these.
  SurfaceDomain cube(test::cube(-1, 1), 1);
  std::mt19937 rng(3);
  std::uniform_int_distribution<int> pick(-8, 8);
  int checked = 0;
  for (int n = 0; n < 20000; ++n)
  {
    const Vec3 p{ pick(rng) / 4.0, pick(rng) / 4.0, pick(rng) / 4.0 };
    const bool inside = std::abs(p.x) <= 1 && std::abs(p.y) <= 1 && std::abs(p.z) <= 1;
    ASSERT_EQ(cube.material(p) == 1, inside) << p.x << " " << p.y << " " << p.z;
    ASSERT_EQ(cube.containsExact(p), inside) << p.x << " " << p.y << " " << p.z;
    ++checked;
  }
  EXPECT_EQ(checked, 20000);
}

TEST(SurfaceDomain, GridShortcutAgreesWithExactTestAndVolumeMatches)
{
  const TriangleSurface sphere = test::icosphere({ 0.3, -0.2, 0.1 }, 2.0, 4); // 2048 triangles
  SurfaceDomain s(sphere, 3);
  EXPECT_NEAR(s.volume(), std::abs(sphere.signedVolume()), 1e-9);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-2.5, 2.5);
  for (int n = 0; n < 50000; ++n)
  {
    const Vec3 p{ u(rng), u(rng), u(rng) };
    ASSERT_EQ(s.material(p) == 3, s.containsExact(p)) << p.x << " " << p.y << " " << p.z;
  }
  auto v = test::sampledVolumes([&](const Vec3& p) { return s.material(p); }, s.bounds(), 120);
  EXPECT_NEAR(v.at(3), s.volume(), 0.01 * s.volume());
}

TEST(SurfaceDomain, LocalParityNearTheSurfaceAgreesWithExactTest)
{
  // Queries in cells that triangles touch count crossings to the cell's reference point: points
  // next to the triangles, on their planes, edges and corners (the axis-aligned cube's faces lie
  // on whole numbers, as a CAD part's do) must get the exact test's answers.
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> noise(-1e-3, 1e-3), u(0.0, 1.0);
  const TriangleSurface sphere = test::icosphere({ 0.1, 0.2, -0.3 }, 1.5, 4);
  SurfaceDomain ball(sphere, 2);
  for (int n = 0; n < 30000; ++n)
  {
    const auto& t = sphere.triangles[rng() % sphere.triangles.size()];
    double a = u(rng), b = u(rng);
    if (a + b > 1)
      a = 1 - a, b = 1 - b;
    const Vec3 on = sphere.points[t[0]] + a * (sphere.points[t[1]] - sphere.points[t[0]]) + b * (sphere.points[t[2]] - sphere.points[t[0]]);
    const Vec3 p = n % 4 == 0 ? sphere.points[t[n % 3]] : on + Vec3{ noise(rng), noise(rng), noise(rng) };
    ASSERT_EQ(ball.material(p) == 2, ball.containsExact(p)) << p.x << " " << p.y << " " << p.z;
  }
  SurfaceDomain cube(test::cube(-2, 3), 1);
  std::uniform_int_distribution<int> grid(-3, 4);
  for (int n = 0; n < 30000; ++n)
  {
    // a point on the lattice of the faces, edges and corners, moved by nothing or a little per axis
    Vec3 p{ double(grid(rng)), double(grid(rng)), double(grid(rng)) };
    for (int a = 0; a < 3; ++a)
      if (rng() % 2)
        p[a] += n % 3 == 0 ? 0.5 : noise(rng);
    const bool inside = p.x >= -2 && p.x <= 3 && p.y >= -2 && p.y <= 3 && p.z >= -2 && p.z <= 3;
    ASSERT_EQ(cube.material(p) == 1, inside) << p.x << " " << p.y << " " << p.z;
  }
}

TEST(SurfaceDomain, CrossingsAreExactTriangleHits)
{
  SurfaceDomain cube(test::cube(0, 1), 1);
  std::vector<double> ts;
  cube.crossings({ 0.3, 0.6, -1 }, { 0.3, 0.6, 3 }, ts);
  std::sort(ts.begin(), ts.end());
  ts.erase(std::unique(ts.begin(), ts.end()), ts.end());
  ASSERT_EQ(ts.size(), 2u);
  EXPECT_NEAR(ts[0], 0.25, 1e-15);
  EXPECT_NEAR(ts[1], 0.5, 1e-15);
  // through a face diagonal (an edge shared by two triangles): still the two faces
  ts.clear();
  cube.crossings({ 0.5, 0.5, -1 }, { 0.5, 0.5, 3 }, ts);
  for (double t : ts)
    EXPECT_TRUE(std::abs(t - 0.25) < 1e-15 || std::abs(t - 0.5) < 1e-15) << t;
}

TEST(SurfaceDomain, OpenOrBrokenSurfacesAreRejectedNamingTheEdges)
{
  TriangleSurface open = test::cube(0, 1);
  open.triangles.pop_back(); // one missing triangle: three open edges
  SurfaceOptions closed;
  closed.insideTest = InsideTest::Closed;
  try
  {
    SurfaceDomain s(open, 1, "implant", closed);
    ADD_FAILURE() << "open surface accepted";
  }
  catch (const InputError& e)
  {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("implant: surface is not closed: 3 open edge(s)"), std::string::npos) << msg;
    EXPECT_NE(msg.find("edge 3 (1, 1, 0) - 5 (1, 0, 1)"), std::string::npos) << msg;
  }
  TriangleSurface nan = test::cube(0, 1);
  nan.points[2].y = std::nan("");
  EXPECT_THROW(SurfaceDomain(nan, 1), InputError);
  TriangleSurface bad = test::cube(0, 1);
  bad.triangles[0][1] = 42;
  EXPECT_THROW(SurfaceDomain(bad, 1), InputError);
  EXPECT_THROW(SurfaceDomain(TriangleSurface{}, 1), InputError);
}
