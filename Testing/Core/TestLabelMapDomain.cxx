// SPDX-License-Identifier: GPL-3.0-or-later
#include "HierarchicalOracle.h"
#include "InputError.h"
#include "LabelMapDomain.h"
#include "TestShapes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

using namespace omesh;

namespace
{
const std::array<double, 9> kIdentity{ 1, 0, 0, 0, 1, 0, 0, 0, 1 };

/// 10 x 8 x 6 grid: label 1 in a block, label 2 in a smaller block, background 0 elsewhere.
std::vector<int> blockLabels(const std::array<int, 3>& d)
{
  std::vector<int> labels(static_cast<size_t>(d[0]) * d[1] * d[2], 0);
  for (int k = 0; k < d[2]; ++k)
    for (int j = 0; j < d[1]; ++j)
      for (int i = 0; i < d[0]; ++i)
      {
        int l = 0;
        if (i >= 2 && i < 8 && j >= 1 && j < 7 && k >= 1 && k < 5)
          l = 1;
        if (i >= 4 && i < 6 && j >= 3 && j < 5 && k >= 2 && k < 4)
          l = 2;
        labels[i + d[0] * (j + d[1] * k)] = l;
      }
  return labels;
}
}

TEST(LabelMapDomain, PointScalarsAreVoxelCentres)
{
  const std::array<int, 3> d{ 10, 8, 6 };
  // point-centred: voxel 0 is centred at the origin, so it spans [-0.25, 0.25) on x with spacing 0.5
  LabelMapDomain lm(d, blockLabels(d), LabelMapDomain::pointCenteredWorldToVoxel({ 0, 0, 0 }, { 0.5, 1, 2 }, kIdentity), 0);
  const BoundingBox b = lm.bounds();
  EXPECT_NEAR(b.min.x, -0.25, 1e-12);
  EXPECT_NEAR(b.max.x, 4.75, 1e-12);
  EXPECT_NEAR(b.min.z, -1.0, 1e-12);
  EXPECT_EQ(lm.material({ 1.0, 1.0, 2.0 }), 1);      // voxel centre (2, 1, 1)
  EXPECT_EQ(lm.material({ 0.76, 1.0, 2.0 }), 1);     // just inside voxel 2's lower x face (0.75)
  EXPECT_EQ(lm.material({ 0.74, 1.0, 2.0 }), kOutside); // background voxel 1
  EXPECT_EQ(lm.materials(), (std::vector<int>{ 1, 2 }));
}

TEST(LabelMapDomain, SampledVolumesEqualVoxelCountTimesVoxelVolume)
{
  const std::array<int, 3> d{ 10, 8, 6 };
  // a rotated, anisotropic, cell-centred grid
  const double c = std::cos(0.3), s = std::sin(0.3);
  const std::array<double, 9> rot{ c, -s, 0, s, c, 0, 0, 0, 1 };
  LabelMapDomain lm(d, blockLabels(d), LabelMapDomain::cellCenteredWorldToVoxel({ 1, -2, 3 }, { 0.5, 0.7, 1.1 }, rot), 0);
  EXPECT_NEAR(lm.voxelVolume(), 0.5 * 0.7 * 1.1, 1e-12);
  const auto counts = lm.voxelCounts();
  EXPECT_EQ(counts.at(1), 6u * 6 * 4 - 2 * 2 * 2);
  EXPECT_EQ(counts.at(2), 8u);
  const auto v = test::sampledVolumes([&](const Vec3& p) { return lm.material(p); }, lm.bounds(), 160);
  for (const auto& [m, n] : counts)
  {
    const double exact = n * lm.voxelVolume();
    EXPECT_NEAR(v.at(m), exact, 0.03 * exact) << "material " << m;
  }
}

TEST(LabelMapDomain, CrossingsAreVoxelFacesWhereTheLabelChanges)
{
  const std::array<int, 3> d{ 10, 8, 6 };
  LabelMapDomain lm(d, blockLabels(d), LabelMapDomain::cellCenteredWorldToVoxel({ 0, 0, 0 }, { 1, 1, 1 }, kIdentity), 0);
  std::vector<double> ts;
  // along x at y = 3.5, z = 2.5 from x = -1 to 11: grid entry 0, 1 at x=2, 2 at x=4, 1 at x=6,
  // 0 at x=8, grid exit at x=10
  lm.crossings({ -1, 3.5, 2.5 }, { 11, 3.5, 2.5 }, ts);
  std::vector<double> xs;
  for (double t : ts)
    xs.push_back(-1 + 12 * t);
  std::sort(xs.begin(), xs.end());
  const std::vector<double> expected{ 0, 2, 4, 6, 8, 10 };
  ASSERT_EQ(xs.size(), expected.size());
  for (size_t i = 0; i < xs.size(); ++i)
    EXPECT_NEAR(xs[i], expected[i], 1e-12);
}

TEST(LabelMapDomain, BadInputIsRejected)
{
  const AffineMap id;
  try
  {
    LabelMapDomain({ 0, 4, 4 }, {}, id, 0, "ct");
    ADD_FAILURE();
  }
  catch (const InputError& e)
  {
    EXPECT_NE(std::string(e.what()).find("ct: label map is empty"), std::string::npos) << e.what();
  }
  try
  {
    LabelMapDomain({ 2, 1, 1 }, { 0, -3 }, id, 0, "ct");
    ADD_FAILURE();
  }
  catch (const InputError& e)
  {
    EXPECT_NE(std::string(e.what()).find("label -3"), std::string::npos) << e.what();
  }
  EXPECT_THROW(LabelMapDomain({ 2, 2, 2 }, { 0, 1 }, id, 0, "ct"), InputError);
  // dims whose product wraps to 0 in 64 bits (2^22 x 2^21 x 2^21) with no labels (found in review)
  EXPECT_THROW(LabelMapDomain({ 1 << 22, 1 << 21, 1 << 21 }, {}, id, 0, "ct"), InputError);
  // a placement with a NaN origin is refused, not inverted into NaN (found by fuzzing)
  try
  {
    const std::array<double, 9> dir{ 1, 0, 0, 0, 1, 0, 0, 0, 1 };
    LabelMapDomain({ 1, 1, 1 }, { 1 }, LabelMapDomain::pointCenteredWorldToVoxel({ NAN, 0, 0 }, { 1, 1, 1 }, dir), 0, "ct");
    ADD_FAILURE();
  }
  catch (const InputError& e)
  {
    EXPECT_NE(std::string(e.what()).find("NaN"), std::string::npos) << e.what();
  }
  // a negative background is fine: it is not a material
  EXPECT_NO_THROW(LabelMapDomain({ 2, 1, 1 }, { -1, 4 }, id, -1, "ct"));
}

TEST(LabelMapDomain, TrilinearBoundariesAreSmoothAndTheirCrossingsExact)
{
  // label 1 below the diagonal i + j < 20 of a 20 x 20 x 4 grid: a staircase for Nearest, close to
  // the plane x + y = 20 for Trilinear
  const std::array<int, 3> d{ 20, 20, 4 };
  std::vector<int> labels(static_cast<size_t>(d[0]) * d[1] * d[2], 0);
  for (int k = 0; k < d[2]; ++k)
    for (int j = 0; j < d[1]; ++j)
      for (int i = 0; i < d[0]; ++i)
        labels[i + d[0] * (j + d[1] * k)] = i + j < 20 ? 1 : 0;
  const AffineMap map = LabelMapDomain::cellCenteredWorldToVoxel({ 0, 0, 0 }, { 1, 1, 1 }, kIdentity);
  for (auto mode : { LabelInterpolation::Nearest, LabelInterpolation::Trilinear })
  {
    SCOPED_TRACE(mode == LabelInterpolation::Nearest ? "Nearest" : "Trilinear");
    HierarchicalOracle o;
    o.add(std::make_shared<LabelMapDomain>(d, labels, map, 0, "diagonal", mode));
    double lo = 1e9, hi = -1e9;
    for (int s = 0; s < 40; ++s)
    {
      const double y = 3.0 + 14.0 * (s + 0.37) / 40.0;
      const Vec3 a{ 0.2, y, 2.0 }, b{ 19.8, y, 2.0 };
      const Intersection x = o.intersect(a, b);
      ASSERT_TRUE(x.found);
      EXPECT_EQ(x.materialBefore, 1);
      EXPECT_EQ(x.materialAfter, kOutside);
      // exact: the material changes right at the reported point
      EXPECT_EQ(o.material(x.point - Vec3{ 1e-7, 0, 0 }), 1);
      EXPECT_EQ(o.material(x.point + Vec3{ 1e-7, 0, 0 }), kOutside);
      lo = std::min(lo, x.point.x + y);
      hi = std::max(hi, x.point.x + y);
    }
    if (mode == LabelInterpolation::Nearest)
      EXPECT_GT(hi - lo, 0.9); // a staircase of one-voxel steps
    else
      EXPECT_LT(hi - lo, 0.5); // within a fraction of a voxel of the plane
    EXPECT_NEAR(0.5 * (lo + hi), 20.5, 0.3);
  }
}
