// SPDX-License-Identifier: GPL-3.0-or-later
#include "BoxDomain.h"
#include "CylinderDomain.h"
#include "HalfSpaceDomain.h"
#include "InputError.h"
#include "SphereDomain.h"
#include "TestShapes.h"

#include <gtest/gtest.h>

#include <random>

using namespace omesh;
using omesh::test::makeBox;
using omesh::test::sampledVolumes;

namespace
{
double sampled(const Domain& d, const BoundingBox& box, int n = 120)
{
  auto v = sampledVolumes([&](const Vec3& p) { return d.material(p); }, box, n);
  return v.empty() ? 0.0 : v.begin()->second;
}
}

TEST(ImplicitDomains, SphereVolumeAndBounds)
{
  SphereDomain s({ 1, 2, 3 }, 2.0, 4);
  EXPECT_EQ(s.material({ 1, 2, 3 }), 4);
  EXPECT_EQ(s.material({ 3, 2, 3 }), 4) << "points on the sphere belong to it (closed set)";
  EXPECT_EQ(s.material({ 3.0001, 2, 3 }), kOutside);
  const BoundingBox b = s.bounds();
  EXPECT_DOUBLE_EQ(b.min.x, -1.0);
  EXPECT_DOUBLE_EQ(b.max.z, 5.0);
  EXPECT_NEAR(sampled(s, b), 4.0 / 3.0 * M_PI * 8.0, 0.01 * 4.0 / 3.0 * M_PI * 8.0);
}

TEST(ImplicitDomains, ScaledSphereIsAnEllipsoid)
{
  SphereDomain s({ 0, 0, 0 }, 1.0, 1);
  // world -> local divides x by 3: an ellipsoid with semi-axes 3, 1, 1
  s.setWorldToLocal(AffineMap::scaleTranslate({ 1.0 / 3.0, 1, 1 }, { 0, 0, 0 }));
  const BoundingBox b = s.bounds();
  EXPECT_NEAR(b.max.x, 3.0, 1e-12);
  EXPECT_NEAR(b.max.y, 1.0, 1e-12);
  EXPECT_NEAR(sampled(s, b), 4.0 / 3.0 * M_PI * 3.0, 0.01 * 4.0 / 3.0 * M_PI * 3.0);
}

TEST(ImplicitDomains, BoxAndCylinderVolumes)
{
  BoxDomain box({ 0, 0, 0 }, { 2, 3, 4 }, 0);
  EXPECT_NEAR(sampled(box, makeBox({ -1, -1, -1 }, { 3, 4, 5 })), 24.0, 0.03 * 24.0);
  EXPECT_EQ(box.material({ 2, 3, 4 }), 0) << "corner belongs to the closed box";

  CylinderDomain cyl({ 0, 0, 0 }, { 1, 1, 0 }, 1.0, 6.0, 2);
  EXPECT_TRUE(cyl.bounded());
  EXPECT_NEAR(sampled(cyl, cyl.bounds(), 140), M_PI * 6.0, 0.02 * M_PI * 6.0);

  CylinderDomain infinite({ 0, 0, 0 }, { 0, 0, 1 }, 1.0, std::numeric_limits<double>::infinity(), 2);
  EXPECT_FALSE(infinite.bounded());
  EXPECT_EQ(infinite.material({ 0.5, 0, 1e6 }), 2);
}

TEST(ImplicitDomains, HalfSpaceFollowsVtkPlaneConvention)
{
  // vtkPlane's function is (p - o).n: negative (inside) on the side the normal points away from.
  HalfSpaceDomain h({ 0, 0, 1 }, { 0, 0, 2 }, 3);
  EXPECT_EQ(h.material({ 5, 5, 0 }), 3);
  EXPECT_EQ(h.material({ 5, 5, 1 }), 3);
  EXPECT_EQ(h.material({ 5, 5, 1.5 }), kOutside);
  EXPECT_FALSE(h.bounded());
}

TEST(ImplicitDomains, CrossingsAreOnTheBoundary)
{
  SphereDomain s({ 0, 0, 0 }, 1.0, 1);
  std::vector<double> ts;
  s.crossings({ -2, 0, 0 }, { 2, 0, 0 }, ts);
  ASSERT_EQ(ts.size(), 2u);
  std::sort(ts.begin(), ts.end());
  EXPECT_NEAR(ts[0], 0.25, 1e-15);
  EXPECT_NEAR(ts[1], 0.75, 1e-15);

  ts.clear();
  BoxDomain box({ 0, 0, 0 }, { 1, 1, 1 }, 0);
  box.crossings({ 0.5, 0.5, -1 }, { 0.5, 0.5, 3 }, ts);
  std::sort(ts.begin(), ts.end());
  ASSERT_EQ(ts.size(), 2u);
  EXPECT_NEAR(ts[0], 0.25, 1e-15);
  EXPECT_NEAR(ts[1], 0.5, 1e-15);
}

TEST(ImplicitDomains, BadParametersAreRejectedWithTheirName)
{
  auto expectError = [](auto make, const std::string& fragment) {
    try
    {
      make();
      ADD_FAILURE() << "no error for " << fragment;
    }
    catch (const InputError& e)
    {
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    }
  };
  expectError([] { SphereDomain({ 0, 0, 0 }, 0.0, 1, "screw"); }, "screw: sphere radius must be positive");
  expectError([] { SphereDomain({ 0, 0, 0 }, -1.0, 1, "screw"); }, "radius must be positive");
  expectError([] { SphereDomain({ 0, 0, 0 }, std::nan(""), 1, "screw"); }, "radius must be positive");
  expectError([] { SphereDomain({ std::nan(""), 0, 0 }, 1.0, 1, "screw"); }, "NaN");
  expectError([] { SphereDomain({ 0, 0, 0 }, 1.0, -2, "screw"); }, "material id -2 is negative");
  expectError([] { HalfSpaceDomain({ 0, 0, 0 }, { 0, 0, 0 }, 1, "cut"); }, "cut: plane normal has zero length");
  expectError([] { BoxDomain({ 0, 0, 0 }, { 1, 0, 1 }, 1, "b"); }, "box bounds are empty");
  expectError([] { CylinderDomain({ 0, 0, 0 }, { 0, 0, 1 }, 1, 0, 1, "c"); }, "cylinder height must be positive");
  expectError(
    [] {
      SphereDomain s({ 0, 0, 0 }, 1.0, 1, "s");
      s.setWorldToLocal(AffineMap({ 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 0 }));
    },
    "singular");
}
