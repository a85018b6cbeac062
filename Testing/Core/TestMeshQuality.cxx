// SPDX-License-Identifier: GPL-3.0-or-later
// The measures of MeshQuality.h and ShapeSummary.h: known tetrahedra, the interface sliver rule's
// shortcut (dihedralAnglesCertainlyAtLeast) against the angle it skips, the one measuring pass.
#include "FieldDataKeys.h"
#include "MeshQuality.h"
#include "ShapeSummary.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <string>

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

TEST(MeshQuality, TetShapeOfKnownTetrahedra)
{
  using namespace omesh;
  const Vec3 a{ 1, 1, 1 }, b{ 1, -1, -1 }, c{ -1, 1, -1 }, d{ -1, -1, 1 };
  const TetShape regular = tetShape(a, b, c, d);
  EXPECT_NEAR(regular.minDihedral, std::acos(1.0 / 3.0) * 180.0 / M_PI, 1e-9);
  EXPECT_NEAR(regular.maxDihedral, regular.minDihedral, 1e-9);
  EXPECT_NEAR(regular.radiusRatio, 1.0, 1e-9);
  EXPECT_NEAR(regular.meanRatio, 1.0, 1e-9);
  EXPECT_NEAR(regular.edgeRatio, 1.0, 1e-9);
  EXPECT_NEAR(regular.radiusEdge, std::sqrt(6.0) / 4.0, 1e-9);
  EXPECT_NEAR(regular.volume, 8.0 / 3.0, 1e-9);
  // the trirectangular corner: r = 1 / (3 + sqrt 3), R = sqrt(3) / 2
  const Vec3 o{ 0, 0, 0 }, x{ 1, 0, 0 }, y{ 0, 1, 0 }, z{ 0, 0, 1 };
  const TetShape corner = tetShape(o, x, y, z);
  EXPECT_NEAR(corner.radiusRatio, 3.0 / (3.0 + std::sqrt(3.0)) / (std::sqrt(3.0) / 2.0), 1e-9);
  EXPECT_NEAR(corner.meanRatio, 12.0 * std::pow(0.5, 2.0 / 3.0) / 9.0, 1e-9);
  EXPECT_NEAR(corner.edgeRatio, 1.0 / std::sqrt(2.0), 1e-9);
  EXPECT_NEAR(corner.maxDihedral, 90.0, 1e-9);
  // the same values as the measures one by one, to the bit
  EXPECT_EQ(corner.minDihedral, minDihedralAngle(o, x, y, z));
  EXPECT_EQ(corner.maxDihedral, maxDihedralAngle(o, x, y, z));
  EXPECT_EQ(corner.radiusEdge, radiusEdgeRatio(o, x, y, z));
  const TetShape flat = tetShape(o, x, y, { 1, 1, 0 });
  EXPECT_EQ(flat.minDihedral, 0.0);
  EXPECT_EQ(flat.maxDihedral, 180.0);
  EXPECT_EQ(flat.radiusRatio, 0.0);
  EXPECT_EQ(flat.meanRatio, 0.0);
}

TEST(MeshQuality, ShapeSummaryIsOnePassOfTheMeasures)
{
  using namespace omesh;
  // two materials, one tetrahedron given negatively oriented: measured as the output writes it
  TetMesh m;
  m.points = { { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 }, { 1, 1, 1 }, { 0.2, 0.2, 0.05 } };
  m.tets = { { 0, 1, 2, 3 }, { 2, 1, 3, 4 }, { 0, 1, 2, 5 } };
  m.tetMaterial = { 1, 2, 1 };
  std::vector<double> smallest(3), largest(3), ratio(3);
  const ShapeSummary s = summariseShapes(m, { smallest.data(), largest.data(), ratio.data() });
  ASSERT_EQ(s.materials.size(), 2u);
  EXPECT_EQ(s.materials.at(1).tetrahedra, 2u);
  EXPECT_EQ(s.all.tetrahedra, 3u);
  const auto volumes = materialVolumes(m);
  EXPECT_NEAR(s.materials.at(1).volume, volumes.at(1), 1e-15);
  EXPECT_NEAR(s.materials.at(2).volume, volumes.at(2), 1e-15);
  double worstRatio = 1.0;
  for (std::size_t t = 0; t < 3; ++t)
  {
    const auto& k = m.tets[t];
    const Vec3 &a = m.points[k[0]], &b = m.points[k[1]], &c = m.points[k[2]], &d = m.points[k[3]];
    EXPECT_NEAR(smallest[t], minDihedralAngle(a, b, c, d), 1e-9);
    EXPECT_NEAR(largest[t], maxDihedralAngle(a, b, c, d), 1e-9);
    EXPECT_NEAR(ratio[t], radiusEdgeRatio(a, b, c, d), 1e-9 * ratio[t]);
    worstRatio = std::min(worstRatio, tetShape(a, b, c, d).radiusRatio);
  }
  EXPECT_EQ(s.all.minDihedral, *std::min_element(smallest.begin(), smallest.end()));
  EXPECT_EQ(s.all.maxDihedral, *std::max_element(largest.begin(), largest.end()));
  EXPECT_NEAR(s.all.meanMinDihedral(), (smallest[0] + smallest[1] + smallest[2]) / 3.0, 1e-12);
  EXPECT_NEAR(s.all.worstRadiusRatio, worstRatio, 1e-12);
  EXPECT_EQ(s.materials.at(2).minDihedral, smallest[1]);
  std::map<std::string, double> st;
  s.addTo(st);
  EXPECT_EQ(st.at(std::string(keys::SHAPE_TETRAHEDRA) + ".material_1"), 2.0);
  EXPECT_EQ(st.at(keys::SHAPE_MIN_DIHEDRAL), s.all.minDihedral);
  // the angle bins count every tetrahedron once, in the bin of its written angle
  std::size_t counted = 0;
  for (std::size_t b = 0; b + 1 < kMinDihedralBinEdges.size(); ++b)
  {
    std::size_t expected = 0;
    for (double angle : smallest)
      expected += angle >= kMinDihedralBinEdges[b] && angle < kMinDihedralBinEdges[b + 1];
    EXPECT_EQ(s.minDihedralBins.counts[b], expected) << "bin " << b;
    counted += s.minDihedralBins.counts[b];
  }
  EXPECT_EQ(counted, 3u);
  EXPECT_EQ(st.at(std::string(keys::SHAPE_MAX_DIHEDRAL_BIN) + ".155_160"), static_cast<double>(s.maxDihedralBins.counts[4]));
}

TEST(MeshQuality, WorstTetrahedraAreThoseAStableSortPutsFirst)
{
  using namespace omesh;
  // keys with ties and a NaN, added in two chunks merged in order: the result is the first five
  // of a stable sort of all the keys (equal keys: the lower index first), NaN never among them
  const std::vector<double> keys = { 3, 1, std::nan(""), 2, 1, 5, 0.5, 2, 1, 7 };
  WorstTets first, second;
  for (std::size_t t = 0; t < keys.size(); ++t)
    (t < 6 ? first : second).add(keys[t], t);
  first.merge(second);
  ASSERT_EQ(first.count, kWorstTetsShown);
  const std::size_t expected[] = { 6, 1, 4, 8, 3 }; // 0.5, then the ones (1, 4, 8), then the first 2
  for (std::size_t i = 0; i < kWorstTetsShown; ++i)
    EXPECT_EQ(first.items[i].second, expected[i]) << "rank " << i;
  WorstTets few;
  few.add(std::nan(""), 0);
  few.add(4, 1);
  EXPECT_EQ(few.count, 1u);
}

TEST(MeshQuality, AngleBinsCountAsNumpyHistogramDoes)
{
  using namespace omesh;
  // [e0, e1), ..., [e(n-2), e(n-1)]: an edge belongs to the bin above it, the last edge to the last
  // bin; values outside every bin and NaN are not counted
  constexpr std::array<double, 4> edges = { 0, 5, 10, 90 };
  BinCounts<4> bins;
  for (double v : { -1.0, 0.0, 4.999, 5.0, 9.0, 10.0, 89.0, 90.0, 90.5, std::nan("") })
    bins.add(edges, v);
  EXPECT_EQ(bins.counts[0], 2u); // 0, 4.999
  EXPECT_EQ(bins.counts[1], 2u); // 5, 9
  EXPECT_EQ(bins.counts[2], 3u); // 10, 89, 90
  BinCounts<4> more;
  more.add(edges, 7.0);
  bins.merge(more);
  EXPECT_EQ(bins.counts[1], 3u);
}
