// SPDX-License-Identifier: GPL-3.0-or-later
// The interface sliver rule's shortcut (dihedralAnglesCertainlyAtLeast) against the angle it skips.
#include "MeshQuality.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace
{
double cosOfDegrees(double degrees) { return std::cos(degrees * M_PI / 180.0); }
}

TEST(MeshQuality, DihedralCertificateNeverContradictsTheAngle)
{
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-10.0, 10.0), unit(0.0, 1.0), hair(-1e-6, 1e-6);
  auto point = [&] { return omesh::Vec3{ u(rng), u(rng), u(rng) }; };
  const double bounds[] = { 1.0, 8.7, 12.0, 30.0, 60.0, 89.9, 90.0, 120.0 };
  int certified = 0, clearlyAbove = 0; // at 12 degrees
  for (int i = 0; i < 30000; ++i)
  {
    omesh::Vec3 p[4] = { point(), point(), point(), point() };
    if (i % 3 == 1) // a sliver: d a hair off the plane of abc
    {
      const double s = unit(rng), t = unit(rng) * (1 - s);
      p[3] = p[0] + s * (p[1] - p[0]) + t * (p[2] - p[0]) + omesh::Vec3{ hair(rng), hair(rng), hair(rng) };
    }
    else if (i % 3 == 2) // a flat one: d exactly on ab's line through a
      p[3] = p[0] + 2.0 * (p[1] - p[0]);
    const double angle = omesh::minDihedralAngle(p[0], p[1], p[2], p[3]);
    clearlyAbove += angle > 12.0 + 1e-6;
    for (double bound : bounds)
    {
      if (omesh::dihedralAnglesCertainlyAtLeast(p[0], p[1], p[2], p[3], cosOfDegrees(bound)))
      {
        ASSERT_GE(angle, bound) << "tet " << i;
        certified += bound == 12.0;
      }
    }
    // bounds right at the angle: the certificate must never claim one above it
    for (double above : { angle * (1 + 1e-12), angle + 1e-9, angle + 1e-6, std::nextafter(angle, 180.0) })
      if (above > 0 && above < 90)
        ASSERT_FALSE(omesh::dihedralAnglesCertainlyAtLeast(p[0], p[1], p[2], p[3], cosOfDegrees(above)))
          << "tet " << i << " angle " << angle;
  }
  // every tetrahedron clearly above the bound is certified (the shortcut pays wherever it can)
  EXPECT_GT(clearlyAbove, 2000);
  EXPECT_GE(certified, clearlyAbove);
}

TEST(MeshQuality, MaxDihedralAngleOfKnownTetrahedra)
{
  using namespace omesh;
  const Vec3 o{ 0, 0, 0 }, x{ 1, 0, 0 }, y{ 0, 1, 0 }, z{ 0, 0, 1 };
  EXPECT_NEAR(maxDihedralAngle(o, x, y, z), 90.0, 1e-9); // the trirectangular corner
  const Vec3 a{ 1, 1, 1 }, b{ 1, -1, -1 }, c{ -1, 1, -1 }, d{ -1, -1, 1 };
  EXPECT_NEAR(maxDihedralAngle(a, b, c, d), std::acos(1.0 / 3.0) * 180.0 / M_PI, 1e-9); // regular: 70.53
  EXPECT_NEAR(maxDihedralAngle(a, b, c, d), minDihedralAngle(a, b, c, d), 1e-9);
  EXPECT_GT(maxDihedralAngle(o, x, { 1, 1, 0.01 }, y), 179.0); // a sliver: four nearly coplanar corners
  EXPECT_NEAR(maxDihedralAngle(o, x, y, { 1, 1, 0 }), 180.0, 1e-9); // flat
}
