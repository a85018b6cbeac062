// SPDX-License-Identifier: GPL-3.0-or-later
#include "BoxDomain.h"
#include "DihedralImprovement.h"
#include "HierarchicalOracle.h"
#include "ImprovementMesh.h"
#include "InterfaceCollapse.h"
#include "LabelMapDomain.h"
#include "MeshQuality.h"
#include "MeshValidity.h"
#include "OracleMesher.h"
#include "SliverPeeler.h"
#include "SphereDomain.h"
#include "SurfaceDomain.h"
#include "TestShapes.h"
#include "TetFlips.h"
#include "VertexMover.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>

using namespace omesh;

namespace
{
/// A ball of radius 0.6 (material 1) in a cube [-1, 1]^3 (material 2) with the cube's edges as
/// feature lines, meshed at radius-edge 2 (many tetrahedra outside [15, 155] before the step).
struct BallInCube
{
  HierarchicalOracle oracle;
  FeatureSegments edges = test::cubeEdges(-1, 1);
  MesherOptions options;
  BallInCube()
  {
    oracle.add(std::make_shared<SphereDomain>(Vec3{ 0.1, -0.05, 0.02 }, 0.6, 1));
    oracle.add(std::make_shared<SurfaceDomain>(test::cube(-1, 1), 2));
    options.criteria.global = { 25.0, 0.25, 0.01, 0.25, 2.0, 0.0 };
    options.seed = 3;
  }
};

bool inWindow(const TetMesh& m, std::size_t t, double lo, double hi)
{
  const auto& q = m.tets[t];
  const auto& p = m.points;
  return minDihedralAngle(p[q[0]], p[q[1]], p[q[2]], p[q[3]]) >= lo &&
    maxDihedralAngle(p[q[0]], p[q[1]], p[q[2]], p[q[3]]) <= hi;
}
}

TEST(DihedralImprovement, WindowQualityIsAtLeastOneExactlyInsideTheWindow)
{
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int inside = 0;
  for (int k = 0; k < 2000; ++k)
  {
    const Vec3 a{ u(rng), u(rng), u(rng) }, b{ u(rng), u(rng), u(rng) }, c{ u(rng), u(rng), u(rng) },
      d{ u(rng), u(rng), u(rng) };
    const bool in = minDihedralAngle(a, b, c, d) >= 15.0 && maxDihedralAngle(a, b, c, d) <= 155.0;
    inside += in;
    EXPECT_EQ(dihedralWindowQuality(a, b, c, d, 15.0, 155.0) >= 1.0, in) << k;
  }
  EXPECT_GT(inside, 50); // both kinds were tried
  EXPECT_LT(inside, 1950);
  EXPECT_EQ(dihedralWindowQuality({ 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 1, 1, 0 }, 15.0, 155.0), -1.0);
}

TEST(DihedralImprovement, AFlatPairBecomesThreeAroundTheEdgeOfItsApexes)
{
  // two flat tetrahedra on an equilateral triangle, apexes 0.1 above and below its centre: their
  // angles at the apex edges are near 180 degrees; around the apex edge they make three good ones
  TetMesh m;
  m.points = { { 1, 0, 0 }, { -0.5, 0.8660254, 0 }, { -0.5, -0.8660254, 0 }, { 0, 0, 0.6 }, { 0, 0, -0.6 } };
  m.points[3].z = 0.1;
  m.points[4].z = -0.1;
  m.pointDimension.assign(5, 0); // every vertex held: only flips may act
  m.tets = { { 0, 1, 2, 3 }, { 0, 2, 1, 4 } };
  m.tetMaterial = { 1, 1 };
  const double volume = materialVolumes(m).at(1);
  HierarchicalOracle around; // material 1 where the pair is (the new tetrahedra's centroids are checked)
  around.add(std::make_shared<BoxDomain>(Vec3{ -2, -2, -2 }, Vec3{ 2, 2, 2 }, 1));
  const auto report = improveDihedralAngles(m, around);
  EXPECT_EQ(report.faceRemovals, 1u);
  ASSERT_EQ(m.tets.size(), 3u);
  EXPECT_NEAR(materialVolumes(m).at(1), volume, 1e-12);
  for (const auto& t : m.tets)
    EXPECT_GT(signedVolume(m.points[t[0]], m.points[t[1]], m.points[t[2]], m.points[t[3]]) *
        signedVolume(m.points[0], m.points[1], m.points[2], m.points[3]),
      0.0)
      << "a flipped tetrahedron is inverted";
  EXPECT_GT(report.minAfter, report.minBefore);
}

TEST(DihedralImprovement, TheFlatPairStaysWhenItsFaceIsAnInterfaceOrItsMaterialsDiffer)
{
  TetMesh m;
  m.points = { { 1, 0, 0 }, { -0.5, 0.8660254, 0 }, { -0.5, -0.8660254, 0 }, { 0, 0, 0.1 }, { 0, 0, -0.1 } };
  m.pointDimension.assign(5, 0);
  m.tets = { { 0, 1, 2, 3 }, { 0, 2, 1, 4 } };
  m.tetMaterial = { 1, 2 };
  m.interfaceTriangles = { { 0, 1, 2 } };
  m.interfaceMaterials = { { 1, 2 } };
  HierarchicalOracle around;
  around.add(std::make_shared<BoxDomain>(Vec3{ -2, -2, -2 }, Vec3{ 2, 2, 2 }, 1));
  const auto report = improveDihedralAngles(m, around);
  EXPECT_EQ(report.faceRemovals + report.edgeRemovals, 0u);
  EXPECT_EQ(m.tets.size(), 2u);
}

namespace
{
/// A flat tetrahedron t = (a, b, c, d) on a ridge: a, b at z = 0 on the x axis, c, d at z = -0.1 on
/// the y axis; its faces abc and abd are the top, acd and bcd lie on two tetrahedra reaching down
/// to e. Edge cd is a feature line (it cannot be flipped away); a is a corner, the rest on the
/// surface. Material 1; with `cap`, material 2 above the ridge (two tetrahedra up to f).
TetMesh ridge(bool cap)
{
  TetMesh m;
  m.points = { { -1, 0, 0 }, { 1, 0, 0 }, { 0, -1, -0.1 }, { 0, 1, -0.1 }, { 0, 0, -1 }, { 0, 0, 1 } };
  m.pointDimension = { 0, 2, 1, 1, 2, 2 };
  auto positive = [&](std::array<int, 4> t) {
    const auto& p = m.points;
    if (signedVolume(p[t[0]], p[t[1]], p[t[2]], p[t[3]]) < 0)
      std::swap(t[2], t[3]);
    return t;
  };
  m.tets = { positive({ 0, 1, 2, 3 }), positive({ 1, 4, 2, 3 }), positive({ 4, 0, 2, 3 }) };
  m.tetMaterial = { 1, 1, 1 };
  if (!cap)
  {
    m.points.pop_back();
    m.pointDimension.pop_back();
  }
  else
  {
    m.tets.push_back(positive({ 0, 1, 2, 5 }));
    m.tets.push_back(positive({ 0, 1, 3, 5 }));
    m.tetMaterial.push_back(2);
    m.tetMaterial.push_back(2);
  }
  const std::vector<std::array<int, 3>> faces = { { 0, 1, 2 }, { 0, 1, 3 }, { 1, 4, 2 }, { 1, 4, 3 }, { 4, 0, 2 },
    { 4, 0, 3 } };
  for (const auto& f : faces)
  {
    m.interfaceTriangles.push_back(f);
    m.interfaceMaterials.push_back({ 1, cap && f[2] < 4 && f[0] == 0 ? 2 : -1 });
  }
  if (cap)
    for (const std::array<int, 3>& f : { std::array<int, 3>{ 0, 2, 5 }, { 1, 2, 5 }, { 0, 3, 5 }, { 1, 3, 5 } })
    {
      m.interfaceTriangles.push_back(f);
      m.interfaceMaterials.push_back({ 2, -1 });
    }
  return m;
}

/// The faces between two materials or on the boundary, each with its two sides' materials.
std::map<std::array<int, 3>, std::array<int, 2>> separatingFaces(const TetMesh& m)
{
  std::map<std::array<int, 3>, std::vector<int>> sides;
  for (std::size_t t = 0; t < m.tets.size(); ++t)
    for (int f = 0; f < 4; ++f)
    {
      std::array<int, 3> face{ m.tets[t][(f + 1) & 3], m.tets[t][(f + 2) & 3], m.tets[t][(f + 3) & 3] };
      std::sort(face.begin(), face.end());
      sides[face].push_back(m.tetMaterial[t]);
    }
  std::map<std::array<int, 3>, std::array<int, 2>> out;
  for (const auto& [face, s] : sides)
  {
    const std::array<int, 2> pair{ std::min(s[0], s.size() > 1 ? s[1] : -1), std::max(s[0], s.size() > 1 ? s[1] : -1) };
    if (pair[0] != pair[1])
      out[face] = pair;
  }
  return out;
}

/// The mesh's interface triangles as separatingFaces gives them.
std::map<std::array<int, 3>, std::array<int, 2>> interfaces(const TetMesh& m)
{
  std::map<std::array<int, 3>, std::array<int, 2>> out;
  for (std::size_t k = 0; k < m.interfaceTriangles.size(); ++k)
  {
    auto face = m.interfaceTriangles[k];
    std::sort(face.begin(), face.end());
    const auto& s = m.interfaceMaterials[k];
    EXPECT_TRUE(out.emplace(face, std::array<int, 2>{ std::min(s[0], s[1]), std::max(s[0], s[1]) }).second)
      << "an interface triangle twice";
  }
  return out;
}
}

TEST(DihedralImprovement, AFlatTetrahedronOnABoundaryRidgeIsPeeledOff)
{
  TetMesh m = ridge(false);
  ASSERT_EQ(interfaces(m), separatingFaces(m));
  HierarchicalOracle body;
  body.add(std::make_shared<BoxDomain>(Vec3{ -2, -2, -2 }, Vec3{ 2, 2, 2 }, 1));
  const auto report = improveDihedralAngles(m, body);
  EXPECT_EQ(report.peeled, 1u);
  ASSERT_EQ(m.tets.size(), 2u);
  EXPECT_EQ(std::count(m.tets.begin(), m.tets.end(), ridge(false).tets[0]), 0) << "the flat one went";
  EXPECT_EQ(interfaces(m), separatingFaces(m)) << "the boundary runs through the peeled one's lower faces";
  const auto validity = checkMeshValidity(m);
  EXPECT_TRUE(validity.valid()) << validity.describe();
}

TEST(DihedralImprovement, AFlatTetrahedronOnAnInterfaceRidgeGoesToTheOtherSide)
{
  TetMesh m = ridge(true);
  ASSERT_EQ(interfaces(m), separatingFaces(m));
  const double before = materialVolumes(m).at(1) + materialVolumes(m).at(2);
  HierarchicalOracle twoMaterials; // 2 above z = 0, 1 below
  twoMaterials.add(std::make_shared<BoxDomain>(Vec3{ -2, -2, 0 }, Vec3{ 2, 2, 2 }, 2));
  twoMaterials.add(std::make_shared<BoxDomain>(Vec3{ -2, -2, -2 }, Vec3{ 2, 2, 2 }, 1));
  const auto report = improveDihedralAngles(m, twoMaterials);
  EXPECT_EQ(report.peeled, 1u);
  EXPECT_EQ(report.outsideAfter, 0u);
  EXPECT_EQ(interfaces(m), separatingFaces(m)) << "the interface runs through the peeled one's lower faces";
  EXPECT_NEAR(materialVolumes(m).at(1) + materialVolumes(m).at(2), before, 1e-12) << "nothing lost";
  for (std::size_t t = 0; t < m.tets.size(); ++t)
    EXPECT_TRUE(inWindow(m, t, 15.0, 155.0)) << t;
}

TEST(DihedralImprovement, AFlatTetrahedronWithAFeatureOnItsRidgeStays)
{
  TetMesh m = ridge(false);
  m.pointDimension[1] = 0; // a and b corners: the ridge ab counts as a feature line
  HierarchicalOracle body;
  body.add(std::make_shared<BoxDomain>(Vec3{ -2, -2, -2 }, Vec3{ 2, 2, 2 }, 1));
  const auto report = improveDihedralAngles(m, body);
  EXPECT_EQ(report.peeled, 0u);
  EXPECT_EQ(m.tets.size(), 3u);
}

TEST(DihedralImprovement, PeelsOnALabelMapKeepItsInterfacesAndVolumes)
{
  // a ball in a shell sampled on voxels (trilinear interfaces): folds of the interfaces between
  // voxels carry thin tetrahedra whose vertices lie where the two labels and the outside meet
  const std::array<int, 3> dims{ 26, 26, 26 };
  std::vector<int> labels;
  for (int k = 0; k < dims[2]; ++k)
    for (int j = 0; j < dims[1]; ++j)
      for (int i = 0; i < dims[0]; ++i)
      {
        const double r = norm(Vec3{ i - 12.3, j - 12.6, k - 12.1 });
        labels.push_back(r < 6.5 ? 1 : r < 9.7 ? 2 : 0);
      }
  HierarchicalOracle oracle;
  oracle.add(std::make_shared<LabelMapDomain>(dims, labels,
    LabelMapDomain::pointCenteredWorldToVoxel({ 0, 0, 0 }, { 1, 1, 1 }, { 1, 0, 0, 0, 1, 0, 0, 0, 1 }), 0, "balls",
    LabelInterpolation::Trilinear));
  MesherOptions on;
  on.criteria.global = { 25.0, 2.0, 0.5, 2.0, 3.0, 0.0 };
  on.seed = 2;
  on.enclosedSliverAngle = 0.0; // refinement would take these tetrahedra itself
  MesherOptions off = on;
  off.improveAngles = false;
  const TetMesh before = meshOracle(oracle, {}, {}, off);
  const TetMesh after = meshOracle(oracle, {}, {}, on);
  EXPECT_GT(after.statistics.at("improvement.peeled"), 0.0) << "the case no longer tests peeling";
  EXPECT_LT(after.statistics.at("improvement.outside_after"), after.statistics.at("improvement.outside_before"));
  EXPECT_EQ(interfaces(after), separatingFaces(after));
  EXPECT_EQ(after.statistics.at("validity.defects"), 0.0);
  const auto vb = materialVolumes(before), va = materialVolumes(after);
  for (int material : { 1, 2 })
    EXPECT_NEAR(va.at(material), vb.at(material), 0.005 * vb.at(material)) << material;
}

TEST(DihedralImprovement, KeepsFeatureLinesInterfacesAndVolumesAndReachesTheWindow)
{
  BallInCube c;
  MesherOptions off = c.options;
  off.improveAngles = false;
  const TetMesh before = meshOracle(c.oracle, c.edges, {}, off);
  const TetMesh after = meshOracle(c.oracle, c.edges, {}, c.options);

  EXPECT_GT(after.statistics.at("improvement.outside_before"), 20.0) << "the case no longer tests the step";
  EXPECT_EQ(after.statistics.at("improvement.outside_after"), 0.0);
  for (std::size_t t = 0; t < after.tets.size(); ++t)
    ASSERT_TRUE(inWindow(after, t, 15.0, 155.0)) << "tetrahedron " << t;
  EXPECT_NEAR(featureCoverage(locateFeatureSegments(after, c.edges), c.edges), 1.0, 1e-12);
  EXPECT_EQ(after.statistics.at("validity.defects"), 0.0);
  EXPECT_LE(after.tets.size(), before.tets.size() * 12 / 10);
  const auto vb = materialVolumes(before), va = materialVolumes(after);
  for (int material : { 1, 2 })
    EXPECT_NEAR(va.at(material), vb.at(material), 0.005 * vb.at(material)) << material;

  // Same refinement, so the same points before the step: feature vertices stay, interface vertices
  // stay on their surface, interface triangles are the same.
  ASSERT_EQ(before.points.size(), after.points.size());
  ASSERT_EQ(before.interfaceTriangles, after.interfaceTriangles);
  std::size_t moved = 0;
  const Vec3 centre{ 0.1, -0.05, 0.02 };
  for (std::size_t v = 0; v < after.points.size(); ++v)
  {
    const Vec3 p = after.points[v], q = before.points[v];
    const bool same = p.x == q.x && p.y == q.y && p.z == q.z;
    if (after.pointDimension[v] == 0)
      EXPECT_TRUE(same) << "corner " << v << " moved";
    if (after.pointDimension[v] == 1 && !same) // slid along its cube edge: two coordinates stay +-1
    {
      const int onFaces = (std::abs(std::abs(p.x) - 1) < 1e-12) + (std::abs(std::abs(p.y) - 1) < 1e-12) +
        (std::abs(std::abs(p.z) - 1) < 1e-12);
      EXPECT_GE(onFaces, 2) << "feature vertex " << v << " left its edge";
    }
    if (after.pointDimension[v] == 2 && !same)
    {
      ++moved;
      const bool onBall = std::abs(norm(q - centre) - 0.6) < 1e-6;
      if (onBall)
        EXPECT_NEAR(norm(p - centre), 0.6, 1e-9) << "vertex " << v << " left the ball's surface";
      else // on a face of the cube: the coordinate that is +-1 stays so
        EXPECT_TRUE(std::abs(std::abs(p.x) - 1) < 1e-12 || std::abs(std::abs(p.y) - 1) < 1e-12 ||
          std::abs(std::abs(p.z) - 1) < 1e-12)
          << "vertex " << v << " left the cube's faces";
    }
  }
  EXPECT_GT(moved, 0u) << "no interface vertex moved: the case no longer tests their projection";
  // the pieces' ends are where their vertices are
  for (const auto& piece : after.segments)
    if (piece.aId >= 0)
      EXPECT_EQ(norm(piece.a - after.points[static_cast<std::size_t>(piece.aId)]), 0.0);

}

TEST(DihedralImprovement, FeatureVerticesSlideAlongTheirStraightSegmentsOnly)
{
  // an L-shaped prism with all 18 edges as feature lines, at radius-edge 3: the worst tetrahedra
  // sit at its edges, whose inner vertices may slide along them
  const TriangleSurface part = test::lPrism(7.0, { 0.37, -1.13, 2.71 });
  HierarchicalOracle o;
  o.add(std::make_shared<SurfaceDomain>(part, 3));
  FeatureSegments edges;
  edges.points = part.points;
  for (int i = 0; i < 6; ++i)
    for (const std::array<int, 2> e : { std::array<int, 2>{ i, (i + 1) % 6 }, { 6 + i, 6 + (i + 1) % 6 }, { i, 6 + i } })
      edges.segments.push_back(e);
  MesherOptions opt;
  opt.criteria.global = { 25.0, 1.5, 0.1, 1.5, 3.0, 0.75 };
  opt.seed = 5;
  const TetMesh m = meshOracle(o, edges, {}, opt);
  if (m.statistics.at("improvement.feature_line_moves") == 0.0) // the clang build refines differently
    GTEST_SKIP() << "no feature vertex slid on this build: nothing to check";
  EXPECT_EQ(m.statistics.at("improvement.outside_after"), 0.0);
  EXPECT_NEAR(featureCoverage(locateFeatureSegments(m, edges), edges), 1.0, 1e-12);
  EXPECT_EQ(m.statistics.at("validity.defects"), 0.0);
  for (std::size_t v = 0; v < m.points.size(); ++v)
  {
    if (m.pointDimension[v] != 1)
      continue;
    double nearest = 1e300;
    for (const auto& s : edges.segments)
      nearest = std::min(nearest, distanceToSegment(m.points[v], edges.points[s[0]], edges.points[s[1]]));
    EXPECT_LT(nearest, 1e-9) << "feature vertex " << v << " left the lines";
  }
}

TEST(DihedralImprovement, OffLeavesTheOutsideTetrahedra)
{
  BallInCube c;
  c.options.improveAngles = false;
  const TetMesh m = meshOracle(c.oracle, c.edges, {}, c.options);
  std::size_t outside = 0;
  for (std::size_t t = 0; t < m.tets.size(); ++t)
    outside += !inWindow(m, t, 15.0, 155.0);
  EXPECT_GT(outside, 0u);
  EXPECT_EQ(m.statistics.count("improvement.outside_before"), 0u);
}

TEST(DihedralImprovement, ProgressReportsTheStepAndAbortStopsIt)
{
  BallInCube c;
  bool seen = false;
  c.options.progress = [&](double, const char* phase) {
    if (std::string(phase) != "quality step")
      return true;
    seen = true;
    return false;
  };
  EXPECT_THROW(meshOracle(c.oracle, c.edges, {}, c.options), MeshingAborted);
  EXPECT_TRUE(seen);
}

// The local changes on their own, on the ImprovementMesh they share.

TEST(DihedralImprovementPhases, TetFlipsTurnsTheFlatPairIntoThreeAroundTheApexEdge)
{
  TetMesh m;
  m.points = { { 1, 0, 0 }, { -0.5, 0.8660254, 0 }, { -0.5, -0.8660254, 0 }, { 0, 0, 0.1 }, { 0, 0, -0.1 } };
  m.pointDimension.assign(5, 0);
  m.tets = { { 0, 1, 2, 3 }, { 0, 2, 1, 4 } };
  m.tetMaterial = { 1, 1 };
  HierarchicalOracle around;
  around.add(std::make_shared<BoxDomain>(Vec3{ -2, -2, -2 }, Vec3{ 2, 2, 2 }, 1));
  const DihedralImprovementOptions options;
  ImprovementMesh state(m, around, options);
  TetFlips flips(state);
  EXPECT_FALSE(flips.removeEdge(0, 1)) << "an edge between two held vertices counts as a feature line";
  const double before = std::min(state.quality(0), state.quality(1));
  ASSERT_TRUE(flips.removeFace(0, 3)); // triangle 012, opposite apex 3
  EXPECT_EQ(state.report().faceRemovals, 1u);
  EXPECT_EQ(state.touched().size(), 3u);
  EXPECT_GT(state.worstOf(state.touched()), before);
  state.writeBack();
  ASSERT_EQ(m.tets.size(), 3u);
  for (const auto& q : m.tets)
    EXPECT_TRUE(std::count(q.begin(), q.end(), 3) == 1 && std::count(q.begin(), q.end(), 4) == 1);
}

TEST(DihedralImprovementPhases, VertexMoverMovesAnInteriorVertexTowardsABetterStar)
{
  // an octahedron (its corners held: on no interface, not interior) around an off-centre vertex
  TetMesh m;
  m.points = { { 1, 0, 0 }, { -1, 0, 0 }, { 0, 1, 0 }, { 0, -1, 0 }, { 0, 0, 1 }, { 0, 0, -1 }, { 0.45, 0.3, 0.2 } };
  m.pointDimension = { 2, 2, 2, 2, 2, 2, 3 };
  for (int x : { 0, 1 })
    for (int y : { 2, 3 })
      for (int z : { 4, 5 })
      {
        std::array<int, 4> q{ x, y, z, 6 };
        const auto& p = m.points;
        if (signedVolume(p[q[0]], p[q[1]], p[q[2]], p[q[3]]) < 0)
          std::swap(q[0], q[1]);
        m.tets.push_back(q);
        m.tetMaterial.push_back(1);
      }
  HierarchicalOracle around;
  around.add(std::make_shared<BoxDomain>(Vec3{ -2, -2, -2 }, Vec3{ 2, 2, 2 }, 1));
  const DihedralImprovementOptions options;
  ImprovementMesh state(m, around, options);
  EXPECT_EQ(state.kind(6), VertexKind::Interior);
  EXPECT_EQ(state.kind(0), VertexKind::Fixed);
  VertexMover mover(state);
  EXPECT_FALSE(mover.moveVertex(0));
  const double before = state.starQuality(6);
  ASSERT_TRUE(mover.moveVertex(6));
  EXPECT_GT(state.starQuality(6), before);
  EXPECT_EQ(state.report().interiorMoves, 1u);
  EXPECT_LT(norm(m.points[6]), norm(Vec3{ 0.45, 0.3, 0.2 })) << "towards the centre";
}

TEST(DihedralImprovementPhases, SliverPeelerPeelsTheFlatTetrahedronOffTheBoundaryRidge)
{
  TetMesh m = ridge(false);
  HierarchicalOracle body;
  body.add(std::make_shared<BoxDomain>(Vec3{ -2, -2, -2 }, Vec3{ 2, 2, 2 }, 1));
  const DihedralImprovementOptions options;
  ImprovementMesh state(m, body, options);
  TetFlips flips(state);
  VertexMover mover(state);
  SliverPeeler peeler(state, flips, mover);
  EXPECT_FALSE(peeler.peel(1)) << "not thin";
  ASSERT_TRUE(peeler.peel(0));
  EXPECT_EQ(state.report().peeled, 1u);
  state.writeBack();
  ASSERT_EQ(m.tets.size(), 2u);
  EXPECT_EQ(interfaces(m), separatingFaces(m)) << "the boundary runs through the peeled one's lower faces";
}

TEST(DihedralImprovementPhases, InterfaceCollapseKeepsTheMeshValidItsInterfacesAndVolumes)
{
  BallInCube c;
  MesherOptions off = c.options;
  off.improveAngles = false;
  TetMesh m = meshOracle(c.oracle, c.edges, {}, off);
  m.segments = locateFeatureSegments(m, c.edges);
  const std::size_t points = m.points.size();
  const auto volumes = materialVolumes(m);
  DihedralImprovementOptions options;
  options.facetDistanceOf = [](int) { return 0.01; }; // the case's facet distance
  ImprovementMesh state(m, c.oracle, options);
  InterfaceCollapse collapse(state);
  // every tenth vertex of the ball's interface, into the first neighbour on it that may take it
  std::size_t collapsed = 0, tried = 0;
  for (int v = 0; v < static_cast<int>(points); ++v)
  {
    if (state.kind(v) != VertexKind::Interface || state.sides(v) != std::array<int, 2>{ 1, 2 } || ++tried % 10)
      continue;
    std::vector<int> neighbours;
    for (int k : state.interfacesAt(v))
      for (int u : m.interfaceTriangles[static_cast<std::size_t>(k)])
        if (u != v)
          neighbours.push_back(u);
    for (int u : neighbours)
      if (collapse.collapse(v, u))
      {
        ++collapsed;
        break;
      }
  }
  EXPECT_GT(collapsed, 5u) << "the case no longer tests collapses";
  EXPECT_EQ(state.report().interfaceCollapses, collapsed);
  state.writeBack();
  EXPECT_EQ(m.points.size(), points - collapsed) << "each collapsed vertex leaves the points";
  const auto validity = checkMeshValidity(m);
  EXPECT_TRUE(validity.valid()) << validity.describe();
  EXPECT_EQ(validity.unusedVertices, 0u);
  EXPECT_EQ(interfaces(m), separatingFaces(m)) << "the interface triangles are the faces between the materials";
  const auto after = materialVolumes(m);
  for (int material : { 1, 2 })
    EXPECT_NEAR(after.at(material), volumes.at(material), 0.01 * volumes.at(material)) << material;
  EXPECT_NEAR(featureCoverage(locateFeatureSegments(m, c.edges), c.edges), 1.0, 1e-12) << "the cube's edges stay";
  for (const auto& piece : m.segments) // renumbered with the points
    if (piece.aId >= 0)
      EXPECT_EQ(norm(piece.a - m.points[static_cast<std::size_t>(piece.aId)]), 0.0);
}
