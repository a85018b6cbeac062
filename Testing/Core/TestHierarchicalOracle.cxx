// SPDX-License-Identifier: GPL-3.0-or-later
#include "BoxDomain.h"
#include "HalfSpaceDomain.h"
#include "HierarchicalOracle.h"
#include "InputError.h"
#include "LabelMapDomain.h"
#include "SphereDomain.h"
#include "SurfaceDomain.h"
#include "TestShapes.h"

#include <gtest/gtest.h>

#include <random>

using namespace omesh;

namespace
{
/// Volume of the part of a ball of radius r below the plane at height h above its centre.
double ballBelow(double r, double h)
{
  const double cap = r - h; // height of the cap above the plane
  return 4.0 / 3.0 * M_PI * r * r * r - M_PI * cap * cap * (3 * r - cap) / 3.0;
}

/// sphere (1) over a cut half-space z > 0.5 over a box (2): priorities and the cut in one scene.
HierarchicalOracle scene()
{
  HierarchicalOracle o;
  o.add(std::make_shared<SphereDomain>(Vec3{ 0, 0, 0 }, 1.0, 1, "ball"));
  auto cut = std::make_shared<HalfSpaceDomain>(Vec3{ 0, 0, 0.5 }, Vec3{ 0, 0, -1 }, 0, "cut");
  cut->setCut(true);
  o.add(cut);
  o.add(std::make_shared<BoxDomain>(Vec3{ -2, -2, -2 }, Vec3{ 2, 2, 2 }, 2, "block"));
  return o;
}
}

TEST(HierarchicalOracle, FirstMatchWinsAndCutsHideLowerPriorities)
{
  const HierarchicalOracle o = scene();
  EXPECT_EQ(o.material({ 0, 0, 0 }), 1);       // ball over block
  EXPECT_EQ(o.material({ 0, 0, 0.9 }), 1);     // ball is above the cut: kept
  EXPECT_EQ(o.material({ 1.5, 0, 0 }), 2);     // block only
  EXPECT_EQ(o.material({ 1.5, 0, 1.0 }), kOutside); // block above the cut plane: cut away
  EXPECT_EQ(o.material({ 3, 0, 0 }), kOutside);
  EXPECT_EQ(o.materials(), (std::vector<int>{ 1, 2 }));
}

TEST(HierarchicalOracle, SampledVolumesMatchTheExactBooleans)
{
  const HierarchicalOracle o = scene();
  const BoundingBox b = o.bounds();
  EXPECT_DOUBLE_EQ(b.volume(), 64.0);
  const auto v = test::sampledVolumes([&](const Vec3& p) { return o.material(p); }, b, 160);
  const double ball = 4.0 / 3.0 * M_PI;
  const double blockBelowCut = 4.0 * 4.0 * 2.5;
  EXPECT_NEAR(v.at(1), ball, 0.01 * ball);
  EXPECT_NEAR(v.at(2), blockBelowCut - ballBelow(1.0, 0.5), 0.01 * blockBelowCut);
}

TEST(HierarchicalOracle, CutAtTopPriorityRemovesEverythingItContains)
{
  HierarchicalOracle o;
  auto hole = std::make_shared<SphereDomain>(Vec3{ 0, 0, 0 }, 0.5, 0, "hole");
  hole->setCut(true);
  o.add(hole);
  o.add(std::make_shared<SurfaceDomain>(test::cube(-1, 1), 3, "cube"));
  const auto v = test::sampledVolumes([&](const Vec3& p) { return o.material(p); }, o.bounds(), 120);
  const double exact = 8.0 - 4.0 / 3.0 * M_PI * 0.125;
  EXPECT_NEAR(v.at(3), exact, 0.01 * exact);
  EXPECT_EQ(o.material({ 0, 0, 0 }), kOutside);
}

TEST(HierarchicalOracle, IntersectLandsOnTheTrueBoundary)
{
  HierarchicalOracle o;
  o.add(std::make_shared<SphereDomain>(Vec3{ 0.1, 0.2, 0.3 }, 0.8, 1, "ball"));
  o.add(std::make_shared<SurfaceDomain>(test::cube(-1, 1), 2, "cube"));
  const std::array<int, 3> d{ 6, 6, 6 };
  std::vector<int> labels(216, 0);
  for (int k = 0; k < 6; ++k)
    for (int j = 0; j < 6; ++j)
      for (int i = 0; i < 6; ++i)
        labels[i + 6 * (j + 6 * k)] = (i + j + k) % 3 == 0 ? 0 : 3 + (i % 2);
  const std::array<double, 9> id{ 1, 0, 0, 0, 1, 0, 0, 0, 1 };
  o.add(std::make_shared<LabelMapDomain>(d, labels,
    LabelMapDomain::cellCenteredWorldToVoxel({ -3, -3, -3 }, { 1, 1, 1 }, id), 0, "labels"));

  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-3.5, 3.5);
  int found = 0;
  for (int n = 0; n < 20000; ++n)
  {
    const Vec3 a{ u(rng), u(rng), u(rng) }, b{ u(rng), u(rng), u(rng) };
    const Intersection x = o.intersect(a, b);
    const int ma = o.material(a), mb = o.material(b);
    if (ma != mb)
      ASSERT_TRUE(x.found) << "materials differ at the ends but no change found";
    if (!x.found)
      continue;
    ++found;
    ASSERT_EQ(x.materialBefore, ma);
    ASSERT_NE(x.materialAfter, x.materialBefore);
    // tolerance stated by intersect(): the change is within 1e-9 |ab| of the returned point
    const Vec3 dir = b - a;
    const double eps = 1e-9;
    if (x.t > eps)
      ASSERT_EQ(o.material(lerp(a, b, x.t - eps)), x.materialBefore);
    if (x.t + eps < 1)
      ASSERT_EQ(o.material(lerp(a, b, x.t + eps)), x.materialAfter) << norm(dir);
  }
  EXPECT_GT(found, 10000);
}

TEST(HierarchicalOracle, EmptyOrUnboundedOraclesAreErrors)
{
  HierarchicalOracle empty;
  EXPECT_EQ(empty.material({ 0, 0, 0 }), kOutside);
  EXPECT_THROW(empty.bounds(), InputError);

  HierarchicalOracle unbounded;
  unbounded.add(std::make_shared<HalfSpaceDomain>(Vec3{ 0, 0, 0 }, Vec3{ 0, 0, 1 }, 1, "floor"));
  try
  {
    unbounded.bounds();
    ADD_FAILURE();
  }
  catch (const InputError& e)
  {
    EXPECT_NE(std::string(e.what()).find("'floor' (Plane) is unbounded"), std::string::npos) << e.what();
  }
}

TEST(HierarchicalOracle, SegmentsOnACutPlaneTouchTheMaterialBelowIt)
{
  // A cut plane through a ball: the rim's chords lie on the closed cut, so every point of them is
  // "outside", yet the ball is right below them (the mesh keeps them as boundary edges).
  HierarchicalOracle o;
  auto cut = std::make_shared<HalfSpaceDomain>(Vec3{ 0, 0, 0.3 }, Vec3{ 0, 0, -1 }, 0, "cut");
  cut->setCut(true);
  o.add(cut);
  o.add(std::make_shared<SphereDomain>(Vec3{ 0, 0, 0 }, 1.0, 1, "ball"));
  const double r = std::sqrt(1.0 - 0.09);
  const Vec3 a{ r, 0, 0.3 }, b{ r * std::cos(0.2), r * std::sin(0.2), 0.3 };
  ASSERT_EQ(o.material(a), kOutside);
  ASSERT_EQ(o.material(0.5 * (a + b)), kOutside);
  EXPECT_TRUE(o.touchesMaterial(a, b));
  EXPECT_TRUE(o.touchesMaterial(Vec3{ -2, 0, 0 }, Vec3{ 2, 0, 0 })); // crosses the ball
  EXPECT_FALSE(o.touchesMaterial(Vec3{ 2, 2, 0 }, Vec3{ 3, 2, 0 }));
  EXPECT_FALSE(o.touchesMaterial(Vec3{ 0, 0, 0.5 }, Vec3{ 0.2, 0, 0.5 })); // cut away, not next to the ball
}
