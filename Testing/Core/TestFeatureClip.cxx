// SPDX-License-Identifier: GPL-3.0-or-later
// Benchmarks/cad_defects item 5: given lines clipped to the meshed domain (FeatureClip.h).
#include "BoxDomain.h"
#include "FeatureClip.h"
#include "FeatureMerge.h"
#include "HalfSpaceDomain.h"
#include "HierarchicalOracle.h"
#include "MeshQuality.h"
#include "MeshValidity.h"
#include "OracleMesher.h"
#include "SurfaceDomain.h"
#include "TestShapes.h"

#include <gtest/gtest.h>

#include <memory>

using namespace omesh;

namespace
{
using test::polyline;

TriangleSurface boxSurface(const Vec3& lo, const Vec3& hi)
{
  TriangleSurface s = test::cube(0.0, 1.0);
  for (Vec3& p : s.points)
    p = { lo.x + p.x * (hi.x - lo.x), lo.y + p.y * (hi.y - lo.y), lo.z + p.z * (hi.z - lo.z) };
  return s;
}

bool hasPoint(const FeatureSegments& f, const Vec3& p)
{
  for (const Vec3& q : f.points)
    if (q.x == p.x && q.y == p.y && q.z == p.z)
      return true;
  return false;
}
}

// A cut plane x <= 0.1 (0.1 has no exact double: the plane is the double 0.1) across a slanted
// line: the piece in the cut is removed and the kept one ends exactly on the plane, x == 0.1.
TEST(FeatureClip, ALineCrossingACutPlaneEndsExactlyOnIt)
{
  HierarchicalOracle o;
  auto cut = std::make_shared<HalfSpaceDomain>(Vec3{ 0.1, 0, 0 }, Vec3{ 1, 0, 0 }, 0, "cut");
  cut->setCut(true);
  o.add(cut);
  o.add(std::make_shared<BoxDomain>(Vec3{ -1, -1, -1 }, Vec3{ 1, 1, 1 }, 1));
  for (const Vec3& start : { Vec3{ -0.7, -0.3, 0.2 }, Vec3{ -0.93, 0.37, -0.61 }, Vec3{ -0.013, 0.77, 0.4 } })
  {
    FeatureSegments f = polyline({ start, { 0.83, 0.29, -0.17 } });
    const FeatureClipCounts c = clipFeatureSegments(f, o);
    ASSERT_EQ(f.segments.size(), 1u);
    EXPECT_EQ(c.split(), 1u);
    EXPECT_EQ(c.owners.at(kUserLine).split, 1u);
    const Vec3 end = f.points[f.segments[0][0]];
    EXPECT_EQ(end.x, 0.1) << "split point " << end.x - 0.1 << " off the plane";
    EXPECT_EQ(f.points[f.segments[0][1]].x, 0.83);
  }
}

// A polyline partly outside the only domain: the segment outside is removed, the one leaving is
// split on the box face (x == 1 exactly), the one inside kept as it is; the edge sizes go along.
TEST(FeatureClip, ALinePartlyOutsideEveryDomainIsClipped)
{
  HierarchicalOracle o;
  o.add(std::make_shared<BoxDomain>(Vec3{ -1, -1, -1 }, Vec3{ 1, 1, 1 }, 1));
  FeatureSegments f = polyline({ { -0.5, 0.1, 0.1 }, { 0.3, 0.1, 0.1 }, { 2.7, 0.3, 0.2 }, { 2.7, 3, 0.2 } });
  f.edgeSizes = { 0.1, 0.2, 0.3 };
  const FeatureClipCounts c = clipFeatureSegments(f, o);
  EXPECT_EQ(c.removed(), 1u);
  EXPECT_EQ(c.split(), 1u);
  ASSERT_EQ(f.segments.size(), 2u);
  ASSERT_EQ(f.edgeSizes.size(), 2u);
  EXPECT_EQ(*f.edgeSizes[0], 0.1);
  EXPECT_EQ(*f.edgeSizes[1], 0.2);
  EXPECT_EQ(f.points.size(), 3u); // the two unused points removed, the split point added
  EXPECT_EQ(f.points[f.segments[1][1]].x, 1.0);
  EXPECT_TRUE(f.validate(o, 2.0).empty());
}

// Lines on the domain's boundary are kept: a box edge lying on the cut plane (the part beside it
// survives) and a line along the housing's face.
TEST(FeatureClip, LinesOnABoundaryBesideMaterialAreKept)
{
  HierarchicalOracle o;
  auto cut = std::make_shared<HalfSpaceDomain>(Vec3{ 0, 0, 0 }, Vec3{ 1, 0, 0 }, 0, "cut");
  cut->setCut(true);
  o.add(cut);
  const TriangleSurface part = boxSurface({ 0, 0, 0 }, { 1, 1, 1 }); // its face x = 0 on the cut plane
  o.add(std::make_shared<SurfaceDomain>(part, 3));
  o.add(std::make_shared<BoxDomain>(Vec3{ -2, -2, -2 }, Vec3{ 2, 2, 2 }, 1));
  FeatureSegments edges = test::sharpEdges(part, 20.0);
  ASSERT_EQ(edges.segments.size(), 12u); // the face diagonals are no sharp edges
  const std::size_t before = edges.segments.size();
  const FeatureClipCounts c = clipFeatureSegments(edges, o, std::vector<int>(before, 1));
  EXPECT_FALSE(c.changed());
  FeatureSegments face = polyline({ { 2, -1, -1 }, { 2, 1, 1 } });
  EXPECT_FALSE(clipFeatureSegments(face, o).changed());
}

// A part's sharp edges where a higher-priority part covers them are no edges of the combined
// domain: clipped at that part's face (exactly), the corners inside removed; a user's line there
// is kept.
TEST(FeatureClip, APartsEdgesCoveredByAHigherPriorityInputAreClippedAUsersLineIsKept)
{
  HierarchicalOracle o;
  o.add(std::make_shared<BoxDomain>(Vec3{ -2, -2, -2 }, Vec3{ 2, 2, 2 }, 2, "block"));
  const TriangleSurface inner = boxSurface({ -0.5, -0.5, -0.5 }, { 3, 0.5, 0.5 });
  o.add(std::make_shared<SurfaceDomain>(inner, 3));
  o.add(std::make_shared<BoxDomain>(Vec3{ -3, -3, -3 }, Vec3{ 5, 3, 3 }, 1));
  FeatureSegments edges = test::sharpEdges(inner, 20.0);
  const std::size_t n = edges.segments.size();
  const FeatureClipCounts c = clipFeatureSegments(edges, o, std::vector<int>(n, 1));
  EXPECT_TRUE(c.changed());
  for (double y : { -0.5, 0.5 })
    for (double z : { -0.5, 0.5 })
    {
      EXPECT_FALSE(hasPoint(edges, { -0.5, y, z }));
      EXPECT_TRUE(hasPoint(edges, { 2.0, y, z }));
      EXPECT_TRUE(hasPoint(edges, { 3.0, y, z }));
    }
  for (const auto& s : edges.segments) // every piece kept lies beyond the block
    EXPECT_GE(std::min(edges.points[s[0]].x, edges.points[s[1]].x), 2.0);
  // the same lines as a user's: inside the block, they are kept
  FeatureSegments own = test::sharpEdges(inner, 20.0);
  EXPECT_FALSE(clipFeatureSegments(own, o).changed());
}

// Study seed 11 in small (cut_part_lines_missing): a box part cut in half by a higher-priority cut
// plane, its sharp edges given. Clipped, the mesh has every kept piece (100 %, no defect); the
// clipped ends are mesh vertices exactly on the plane. Given unclipped, the validity check still
// reports the pieces beyond the plane as missing: it counts what it is given.
TEST(FeatureClip, ACutPartsEdgesClippedMeshWithoutMissingPieces)
{
  HierarchicalOracle o;
  auto cut = std::make_shared<HalfSpaceDomain>(Vec3{ -1, 0, 0 }, Vec3{ 1, 0, 0 }, 0, "cut");
  cut->setCut(true);
  o.add(cut);
  const TriangleSurface part = boxSurface({ -3, 0, 0 }, { 1, 1, 1 });
  o.add(std::make_shared<SurfaceDomain>(part, 4));
  o.add(std::make_shared<BoxDomain>(Vec3{ -4, -2, -2 }, Vec3{ 4, 3, 3 }, 1));
  const FeatureSegments given = test::sharpEdges(part, 20.0);
  FeatureSegments clipped = given;
  const FeatureClipCounts c = clipFeatureSegments(clipped, o, std::vector<int>(given.segments.size(), 1));
  EXPECT_EQ(c.split(), 4u);
  mergeFeatureSegments(clipped);
  MesherOptions opt;
  opt.criteria.global = { 25.0, 0.5, 0.05, 0.6, 2.0, 0.4 }; // angle, facet size, distance, cell size, radius-edge, edge
  opt.seed = 1;
  const TetMesh m = meshOracle(o, clipped, {}, opt);
  EXPECT_EQ(m.statistics.at("validity.defects"), 0.0);
  EXPECT_EQ(m.statistics.at("feature_coverage"), 1.0);
  for (const auto& w : m.warnings)
    EXPECT_EQ(w.find("outside every domain"), std::string::npos) << w;
  std::size_t onPlane = 0;
  for (const Vec3& p : m.points)
    onPlane += p.x == -1.0 && (p.y == 0.0 || p.y == 1.0) && (p.z == 0.0 || p.z == 1.0);
  EXPECT_EQ(onPlane, 4u);
  // the same mesh checked against the lines as given: the removed half's pieces are missing
  TetMesh unclipped = m;
  unclipped.segments = locateFeatureSegments(unclipped, given);
  EXPECT_LT(featureCoverage(unclipped.segments, given), 0.9);
  const MeshValidity v = checkMeshValidity(unclipped, [&o](const Vec3& p) { return o.material(p); });
  EXPECT_GT(v.missingSegmentPieces, 0u);
  EXPECT_FALSE(v.valid());
}
