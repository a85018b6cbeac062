// SPDX-License-Identifier: GPL-3.0-or-later
// Each defect of MeshValidity built by hand on a small valid mesh, and seen.
#include "FieldDataKeys.h"
#include "MeshQuality.h"
#include "MeshValidity.h"
#include "ShapeSummary.h"
#include "TestShapes.h"
#include "WorkerThreads.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <random>

using namespace omesh;

namespace
{
/// Two positively oriented unit-size tetrahedra sharing the face (0, 1, 2), materials 1 and 2.
TetMesh twoTets()
{
  TetMesh m;
  m.points = { { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 }, { 0.4, 0.4, -1 } };
  m.tets = { { 0, 1, 2, 3 }, { 0, 2, 1, 4 } };
  m.tetMaterial = { 1, 2 };
  m.pointDimension = { 2, 2, 2, 3, 3 };
  return m;
}
}

TEST(MeshValidity, ValidMeshHasNoDefects)
{
  std::vector<unsigned char> flags;
  const MeshValidity v = checkMeshValidity(twoTets(), {}, {}, &flags);
  EXPECT_TRUE(v.valid()) << v.describe();
  EXPECT_EQ(v.describe(), "");
  EXPECT_EQ(flags, std::vector<unsigned char>(2, 0));
  EXPECT_GT(v.medianEdge, 0.9);
}

TEST(MeshValidity, DuplicateVertexIsSeen)
{
  TetMesh m = twoTets();
  m.points.push_back(m.points[3] + Vec3{ 1e-13, 0, 0 }); // a second copy of the apex
  m.tets.push_back({ 1, 2, 5, 4 });                       // used by a (flat-free) tetrahedron
  m.tetMaterial.push_back(2);
  std::vector<unsigned char> flags;
  const MeshValidity v = checkMeshValidity(m, {}, {}, &flags);
  EXPECT_EQ(v.duplicateVertices, 2u); // both copies
  EXPECT_TRUE(flags[0] & kDuplicateVertex);
  EXPECT_TRUE(flags[2] & kDuplicateVertex);
  EXPECT_FALSE(flags[1] & kDuplicateVertex);
}

TEST(MeshValidity, MicroFlatAndInvertedTetrahedraAreSeen)
{
  TetMesh m = twoTets();
  const int base = static_cast<int>(m.points.size());
  const double e = 1e-6; // a whole tetrahedron far below 1e-4 x the median edge
  for (const Vec3& p : { Vec3{ 5, 5, 5 }, Vec3{ 5 + e, 5, 5 }, Vec3{ 5, 5 + e, 5 }, Vec3{ 5, 5, 5 + e } })
    m.points.push_back(p);
  m.tets.push_back({ base, base + 1, base + 2, base + 3 });
  // a flat one: the fourth point in the plane of the first three
  m.points.push_back({ 3, 0, 0 });
  m.points.push_back({ 4, 0, 0 });
  m.points.push_back({ 3, 1, 0 });
  m.points.push_back({ 3.5, 0.5, 0 });
  m.tets.push_back({ base + 4, base + 5, base + 6, base + 7 });
  // an inverted one: the first tetrahedron with two vertices swapped
  m.tets.push_back({ 1, 0, 2, 3 });
  m.tetMaterial.resize(m.tets.size(), 1);
  std::vector<unsigned char> flags;
  const MeshValidity v = checkMeshValidity(m, {}, {}, &flags);
  EXPECT_EQ(v.microTetrahedra, 1u);
  EXPECT_TRUE(flags[2] & kMicro);
  EXPECT_EQ(v.flatTetrahedra, 1u);
  EXPECT_TRUE(flags[3] & kFlat);
  EXPECT_EQ(v.invertedTetrahedra, 1u);
  EXPECT_TRUE(flags[4] & kInverted);
  EXPECT_FALSE(v.valid());
}

TEST(MeshValidity, MicroTetrahedraThatAreMostOfTheMeshAreSeen)
{
  // ten unit tetrahedra and a hundred of edge 1e-6 around one point (as a refinement that
  // converged there until the vertex budget): the median edge is the tiny ones', not a reference
  TetMesh m;
  auto add = [&m](const Vec3& at, double e) {
    const int base = static_cast<int>(m.points.size());
    for (const Vec3& p : { at, at + Vec3{ e, 0, 0 }, at + Vec3{ 0, e, 0 }, at + Vec3{ 0, 0, e } })
      m.points.push_back(p);
    m.tets.push_back({ base, base + 1, base + 2, base + 3 });
  };
  for (int i = 0; i < 10; ++i)
    add({ 2.0 * i, 0, 0 }, 1.0);
  for (int i = 0; i < 100; ++i)
    add({ 50 + 1e-5 * i, 0, 0 }, 1e-6);
  m.tetMaterial.assign(m.tets.size(), 1);
  const MeshValidity v = checkMeshValidity(m, {}, {});
  EXPECT_LT(v.medianEdge, 1e-5);
  EXPECT_EQ(v.microTetrahedra, 100u);
}

TEST(MeshValidity, MicroIsRelativeToTheExactMedianAlsoNearTheThreshold)
{
  // Micro is flagged in the pass that finds the median, before the median is known, from the
  // bounds of its bin (about 3 % wide); tetrahedra between those bounds wait for the median. Here
  // sixteen regular tetrahedra of edge 1.01 (the median, L) and three small ones of longest edge
  // 0.995, 1.005 and 1.02 x 1e-4: the first two are below 1e-4 L, the last is not, and the last
  // two lie between the bounds of the median's bin.
  TetMesh m;
  auto add = [&m](const Vec3& at, double edge) {
    const double s = edge / (2.0 * std::sqrt(2.0));
    const int base = static_cast<int>(m.points.size());
    for (const Vec3& p : { Vec3{ 1, 1, 1 }, Vec3{ -1, 1, -1 }, Vec3{ 1, -1, -1 }, Vec3{ -1, -1, 1 } })
      m.points.push_back(at + s * p);
    m.tets.push_back({ base, base + 1, base + 2, base + 3 });
  };
  for (int i = 0; i < 16; ++i)
    add({ 3.0 * i, 0, 0 }, 1.01);
  add({ 0, 5, 0 }, 0.995e-4);
  add({ 0, 6, 0 }, 1.005e-4);
  add({ 0, 7, 0 }, 1.02e-4);
  m.tetMaterial.assign(m.tets.size(), 1);
  std::vector<unsigned char> flags;
  const MeshValidity v = checkMeshValidity(m, {}, {}, &flags);
  EXPECT_NEAR(v.medianEdge, 1.01, 1e-12);
  EXPECT_EQ(v.microTetrahedra, 2u);
  EXPECT_TRUE(flags[16] & kMicro);
  EXPECT_TRUE(flags[17] & kMicro);
  EXPECT_FALSE(flags[18] & kMicro);
}

TEST(MeshValidity, FaceSharedByThreeTetrahedraIsSeen)
{
  TetMesh m = twoTets();
  m.points.push_back({ 0.2, 0.2, 2 });
  m.tets.push_back({ 0, 1, 2, 5 }); // a second tetrahedron above face (0, 1, 2)
  m.tetMaterial.push_back(1);
  std::vector<unsigned char> flags;
  const MeshValidity v = checkMeshValidity(m, {}, {}, &flags);
  EXPECT_EQ(v.nonManifoldFaces, 1u);
  for (unsigned char f : flags)
    EXPECT_TRUE(f & kNonManifoldFace);
}

/// A cube of n^3 Kuhn-split cells (6 positively oriented tetrahedra each), its vertices numbered in
/// a shuffled order so that a face's smallest vertex may be any of its corners.
TetMesh kuhnCube(int n)
{
  TetMesh m;
  const int side = n + 1, count = side * side * side;
  std::vector<int> number(count);
  for (int i = 0; i < count; ++i)
    number[i] = (i * 37) % count; // 37 is prime to 5^3: a permutation
  m.points.resize(count);
  auto id = [&](int i, int j, int k) { return number[(k * side + j) * side + i]; };
  for (int k = 0; k < side; ++k)
    for (int j = 0; j < side; ++j)
      for (int i = 0; i < side; ++i)
        m.points[id(i, j, k)] = { double(i), double(j), double(k) };
  const int path[6][3] = { { 0, 1, 2 }, { 0, 2, 1 }, { 1, 0, 2 }, { 1, 2, 0 }, { 2, 0, 1 }, { 2, 1, 0 } };
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        for (const auto& axes : path)
        {
          int c[3] = { i, j, k };
          std::array<int, 4> t;
          t[0] = id(c[0], c[1], c[2]);
          for (int s = 0; s < 3; ++s)
          {
            ++c[axes[s]];
            t[s + 1] = id(c[0], c[1], c[2]);
          }
          if (signedVolume(m.points[t[0]], m.points[t[1]], m.points[t[2]], m.points[t[3]]) < 0)
            std::swap(t[2], t[3]);
          m.tets.push_back(t);
        }
  m.tetMaterial.assign(m.tets.size(), 1);
  return m;
}

TEST(MeshValidity, ThirdTetrahedronOnAnInteriorFaceIsSeenInALargerMesh)
{
  TetMesh m = kuhnCube(4);
  ASSERT_EQ(m.points.size(), 125u);
  const MeshValidity clean = checkMeshValidity(m);
  EXPECT_TRUE(clean.valid()) << clean.describe();
  // an interior face: three corners of a tetrahedron of cell (2, 2, 2), in the middle of the cube,
  // whose two tetrahedra get a third on the same face
  const std::array<int, 4> middle = m.tets[6 * ((2 * 4 + 2) * 4 + 2)];
  m.points.push_back({ 2.1, 2.2, 2.3 });
  m.tets.push_back({ middle[0], middle[1], middle[2], static_cast<int>(m.points.size()) - 1 });
  m.tetMaterial.push_back(1);
  std::vector<unsigned char> flags;
  const MeshValidity v = checkMeshValidity(m, {}, {}, &flags);
  EXPECT_EQ(v.nonManifoldFaces, 1u);
  EXPECT_EQ(std::count_if(flags.begin(), flags.end(), [](unsigned char f) { return (f & kNonManifoldFace) != 0; }), 3);
}

TEST(MeshValidity, DuplicatesAreThePairsABruteForceSearchFinds)
{
  // jittered grid vertices, and copies of some at 0.3-3 times the duplicate distance in random
  // directions (across the search grid's cell faces too), each copy used by a tetrahedron
  std::mt19937 random(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  TetMesh m = kuhnCube(6);
  for (Vec3& p : m.points)
    p = p + 0.2 * Vec3{ unit(random), unit(random), unit(random) };
  ValidityThresholds th;
  th.duplicate = 1e-4;
  const std::size_t original = m.tets.size();
  for (int copy = 0; copy < 200; ++copy)
  {
    const std::array<int, 4> t = m.tets[static_cast<std::size_t>(copy * 7) % original];
    Vec3 direction{ unit(random), unit(random), unit(random) };
    direction = (1.0 / norm(direction)) * direction;
    const double distance = (0.3 + 2.7 * (unit(random) + 1.0) / 2.0) * th.duplicate; // x L, L about 1
    m.points.push_back(m.points[t[0]] + distance * direction);
    m.tets.push_back({ static_cast<int>(m.points.size()) - 1, t[1], t[2], t[3] });
    m.tetMaterial.push_back(1);
  }
  const MeshValidity v = checkMeshValidity(m, {}, th);
  double volume = 0.0;
  for (const auto& k : m.tets)
    volume += std::abs(signedVolume(m.points[k[0]], m.points[k[1]], m.points[k[2]], m.points[k[3]]));
  const double tol = th.duplicate * validityLength(v.medianEdge, volume, m.tets.size());
  std::size_t expected = 0;
  for (std::size_t a = 0; a < m.points.size(); ++a)
  {
    bool dup = false;
    for (std::size_t b = 0; b < m.points.size() && !dup; ++b)
      dup = a != b && norm(m.points[a] - m.points[b]) < tol;
    expected += dup;
  }
  EXPECT_GT(expected, 50u);
  EXPECT_LT(expected, 400u);
  EXPECT_EQ(v.duplicateVertices, expected);
}

TEST(MeshValidity, BadIndicesAreSeen)
{
  TetMesh m = twoTets();
  m.tets.push_back({ 0, 1, 1, 3 });  // repeated
  m.tets.push_back({ 0, 1, 2, 99 }); // out of range
  m.tetMaterial.resize(4, 1);
  const MeshValidity v = checkMeshValidity(m);
  EXPECT_EQ(v.badIndices, 2u);
}

TEST(MeshValidity, MaterialMismatchNeedsFourInteriorVertices)
{
  TetMesh m = twoTets();
  auto oracle = [](const Vec3& p) { return p.z > 0 ? 1 : 3; }; // below z = 0 is material 3, not 2
  // the lower tetrahedron has three interface vertices: its centroid may lie across the interface
  EXPECT_EQ(checkMeshValidity(m, oracle).materialMismatches, 0u);
  m.pointDimension = { 3, 3, 3, 3, 3 }; // all inside: the oracle must agree at the centroid
  std::vector<unsigned char> flags;
  const MeshValidity v = checkMeshValidity(m, oracle, {}, &flags);
  EXPECT_EQ(v.materialMismatches, 1u);
  EXPECT_TRUE(flags[1] & kMaterialMismatch);
  EXPECT_FALSE(flags[0] & kMaterialMismatch);
}

TEST(MeshValidity, MissingSegmentPiecesAreCounted)
{
  TetMesh m = twoTets();
  TetMesh::Segment present, missing;
  present.present = true;
  m.segments = { present, missing, missing };
  const MeshValidity v = checkMeshValidity(m);
  EXPECT_EQ(v.missingSegmentPieces, 2u);
  EXPECT_NE(v.describe().find("2 constrained segment pieces missing"), std::string::npos);
}

using test::polyline;

// CGAL's protecting balls join consecutive ball centres; where the line runs straight through an
// input point between them, that edge is the line (the measure once called both pieces missing).
// Through a bend, or past a junction, it is not.
TEST(MeshValidity, AnEdgeStraightThroughInputPointsCoversTheLine)
{
  const TetMesh m = twoTets(); // edge (1, 2) from (1, 0, 0) to (0, 1, 0)
  const FeatureSegments straight = polyline({ { 1, 0, 0 }, { 0.5, 0.5, 0 }, { 0, 1, 0 } });
  auto pieces = locateFeatureSegments(m, straight);
  ASSERT_EQ(pieces.size(), 2u);
  EXPECT_TRUE(pieces[0].present && pieces[1].present);
  EXPECT_DOUBLE_EQ(featureCoverage(pieces, straight), 1.0);

  // two input points between the edge's ends, the middle segment without a mesh vertex
  const FeatureSegments twoPoints = polyline({ { 0, 1, 0 }, { 0.25, 0.75, 0 }, { 0.75, 0.25, 0 }, { 1, 0, 0 } });
  EXPECT_DOUBLE_EQ(featureCoverage(locateFeatureSegments(m, twoPoints), twoPoints), 1.0);

  const FeatureSegments bent = polyline({ { 1, 0, 0 }, { 0.5, 0.5, 0.01 }, { 0, 1, 0 } });
  pieces = locateFeatureSegments(m, bent);
  EXPECT_FALSE(pieces[0].present || pieces[1].present);
  EXPECT_DOUBLE_EQ(featureCoverage(pieces, bent), 0.0);

  FeatureSegments junction = straight; // a third line leaves the middle point: it must be a vertex
  junction.points.push_back({ 0.5, 0.5, 0.5 });
  junction.segments.push_back({ 1, 3 });
  pieces = locateFeatureSegments(m, junction);
  EXPECT_EQ(std::count_if(pieces.begin(), pieces.end(), [](const TetMesh::Segment& p) { return p.present; }), 0);
}

TEST(MeshValidity, StatisticsNameEveryCount)
{
  TetMesh m = twoTets();
  m.tets.push_back({ 1, 0, 2, 3 });
  m.tetMaterial.push_back(1);
  const MeshValidity v = checkMeshValidity(m);
  const auto pairs = v.asStatistics();
  const std::map<std::string, double> st(pairs.begin(), pairs.end());
  EXPECT_EQ(st.at("validity.inverted_tetrahedra"), 1.0);
  EXPECT_EQ(st.at("validity.defects"), static_cast<double>(v.defects()));
}

// A node without an element is a zero row of a stiffness matrix: a defect, named.
TEST(MeshValidity, UnusedVertexIsSeen)
{
  TetMesh m = twoTets();
  m.points.push_back({ 5, 5, 5 });
  m.pointDimension.push_back(2);
  const MeshValidity v = checkMeshValidity(m);
  EXPECT_EQ(v.unusedVertices, 1u);
  EXPECT_EQ(v.defects(), 1u);
  EXPECT_NE(v.describe().find("1 vertices no tetrahedron uses"), std::string::npos);
}

// A tetrahedron with every vertex on an interface whose centroid lies in another material fills
// part of that material: counted (not a defect) when it reaches across farther than the finer
// facet distance of the two, by its smallest altitude.
TEST(MeshValidity, TetrahedraAcrossABoundaryAreCountedAboveTheFacetDistance)
{
  TetMesh m = twoTets();
  m.pointDimension = { 2, 2, 2, 2, 3 };                          // the upper one: every vertex on interfaces
  auto oracle = [](const Vec3&) { return 2; }; // the upper one is material 1, the oracle says 2
  const double h = smallestAltitude(m.points[0], m.points[1], m.points[2], m.points[3]); // 1/sqrt(3)
  ValidityThresholds th;
  auto counted = [&](double d1, double d2) {
    th.facetDistanceOf = [=](int material) { return material == 1 ? d1 : d2; };
    return checkMeshValidity(m, oracle, th);
  };
  MeshValidity v = counted(0.1, 0.5);
  EXPECT_EQ(v.acrossBoundaryTetrahedra, 1u);
  EXPECT_NEAR(v.acrossBoundaryVolume, 1.0 / 6.0, 1e-12);
  EXPECT_TRUE(v.valid()); // a fidelity figure, not a defect
  EXPECT_EQ(counted(0.5, 0.1).acrossBoundaryTetrahedra, 1u); // the finer of the two
  EXPECT_EQ(counted(0.9 * h, 0.0).acrossBoundaryTetrahedra, 1u); // one without a facet distance
  EXPECT_EQ(counted(1.1 * h, 2.0).acrossBoundaryTetrahedra, 0u); // thinner than both
  EXPECT_EQ(counted(0.0, 0.0).acrossBoundaryTetrahedra, 0u);     // neither has one
  m.pointDimension[3] = 3; // an inside vertex: the material check's business, not this one
  EXPECT_EQ(counted(0.1, 0.1).acrossBoundaryTetrahedra, 0u);
  m.pointDimension[3] = 2;
  th.facetDistanceOf = {};
  EXPECT_EQ(checkMeshValidity(m, oracle, th).acrossBoundaryTetrahedra, 0u); // not asked for
  const auto pairs = counted(0.1, 0.1).asStatistics();
  const std::map<std::string, double> st(pairs.begin(), pairs.end());
  EXPECT_EQ(st.at("validity.across_boundary_tetrahedra"), 1.0);
  EXPECT_NEAR(st.at("validity.across_boundary_volume"), 1.0 / 6.0, 1e-12);
}

TEST(MeshQuality, SmallestAltitudeIsTheHeightOverTheLargestFace)
{
  const Vec3 o{ 0, 0, 0 }, x{ 1, 0, 0 }, y{ 0, 1, 0 }, z{ 0, 0, 1 };
  EXPECT_NEAR(smallestAltitude(o, x, y, z), 1.0 / std::sqrt(3.0), 1e-15); // over the face x + y + z = 1
  EXPECT_NEAR(smallestAltitude(o, x, y, 0.01 * z), 0.01 / std::sqrt(1.0 + 2.0 * 1e-4) * 1.0, 1e-6);
  EXPECT_EQ(smallestAltitude(o, x, y, Vec3{ 1, 1, 0 }), 0.0); // flat
}

TEST(MeshValidity, MedianAndShortestEdgeAreThoseOfAllEdgeLengths)
{
  // random tetrahedra over eight orders of magnitude of size, with many equal lengths (a copy of
  // each tetrahedron): the check's binned median must be the element of rank n/2 of the lengths
  std::mt19937 random(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int round = 0; round < 20; ++round)
  {
    TetMesh m;
    const int count = 1 + round * 37;
    for (int t = 0; t < count; ++t)
    {
      const double size = std::pow(10.0, -4.0 + 8.0 * unit(random));
      const Vec3 o{ unit(random) * 100, unit(random) * 100, unit(random) * 100 };
      const int base = static_cast<int>(m.points.size());
      m.points.push_back(o);
      m.points.push_back(o + Vec3{ size, 0, 0 });
      m.points.push_back(o + Vec3{ 0, size * (0.5 + unit(random)), 0 });
      m.points.push_back(o + Vec3{ 0, 0, size * (0.5 + unit(random)) });
      m.tets.push_back({ base, base + 1, base + 2, base + 3 });
      m.tetMaterial.push_back(1);
      if (t % 3 == 0)
      {
        m.tets.push_back({ base, base + 1, base + 2, base + 3 }); // the same edges again
        m.tetMaterial.push_back(1);
      }
    }
    std::vector<double> lengths;
    for (const auto& k : m.tets)
      for (int i = 0; i < 4; ++i)
        for (int j = i + 1; j < 4; ++j)
          lengths.push_back(norm(m.points[k[i]] - m.points[k[j]]));
    std::sort(lengths.begin(), lengths.end());
    const MeshValidity v = checkMeshValidity(m);
    EXPECT_EQ(v.medianEdge, lengths[lengths.size() / 2]) << "round " << round;
    EXPECT_EQ(v.shortestEdge, lengths.front()) << "round " << round;
  }
}

TEST(MeshValidity, FiguresAreTheSameOnOneAndTwoThreads)
{
  // A grid of 36^3 cubes of six tetrahedra each (279,936: several chunks of every pass), two
  // materials, jittered points, one tetrahedron inverted and one with bad indices: every figure,
  // statistic, flag, cell array and separating face is the same on one and on two threads (the
  // chunks are merged in their order, not the threads').
  const int n = 36;
  TetMesh m;
  std::mt19937 random(7);
  std::uniform_real_distribution<double> jitter(-0.2, 0.2);
  auto id = [n](int i, int j, int k) { return (k * (n + 1) + j) * (n + 1) + i; };
  for (int k = 0; k <= n; ++k)
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i)
      {
        const bool inside = i > 0 && j > 0 && k > 0 && i < n && j < n && k < n;
        m.points.push_back(Vec3{ double(i), double(j), double(k) } +
          (inside ? Vec3{ jitter(random), jitter(random), jitter(random) } : Vec3{ 0, 0, 0 }));
      }
  // Kuhn's six tetrahedra of a cube along its diagonal 0-7 (corner c at bits x=1, y=2, z=4)
  const int paths[6][2] = { { 1, 3 }, { 1, 5 }, { 2, 3 }, { 2, 6 }, { 4, 5 }, { 4, 6 } };
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
      {
        auto corner = [&](int c) { return id(i + (c & 1), j + ((c >> 1) & 1), k + ((c >> 2) & 1)); };
        for (const auto& p : paths)
        {
          std::array<int, 4> t = { corner(0), corner(p[0]), corner(p[1]), corner(7) };
          if (signedVolume(m.points[t[0]], m.points[t[1]], m.points[t[2]], m.points[t[3]]) < 0)
            std::swap(t[0], t[1]);
          m.tets.push_back(t);
          m.tetMaterial.push_back(i < n / 2 ? 1 : 2);
        }
      }
  std::swap(m.tets[1000][0], m.tets[1000][1]); // inverted
  m.tets[2000][3] = m.tets[2000][0];           // bad indices
  struct Figures
  {
    std::map<std::string, double> statistics;
    std::vector<unsigned char> flags;
    std::vector<double> smallest, largest, ratio;
    std::vector<TetMesh::SeparatingFace> separating;
  };
  auto check = [&m](int threads) {
    Figures f;
    f.smallest.resize(m.tets.size());
    f.largest.resize(m.tets.size());
    f.ratio.resize(m.tets.size());
    runOnThreads(threads, [&] {
      ShapeSummary shapes;
      ValidityByproducts b;
      b.shapes = &shapes;
      b.separatingFaces = &f.separating;
      b.shapeArrays = { f.smallest.data(), f.largest.data(), f.ratio.data() };
      const MeshValidity v = checkMeshValidity(m, {}, {}, &f.flags, b);
      for (const auto& [name, value] : v.asStatistics())
        f.statistics[name] = value;
      shapes.addTo(f.statistics);
    });
    return f;
  };
  const Figures one = check(1), two = check(2);
  EXPECT_EQ(one.statistics.at(keys::VALIDITY_INVERTED_TETRAHEDRA), 1.0);
  EXPECT_EQ(one.statistics.at(keys::VALIDITY_BAD_VERTEX_INDICES), 1.0);
  EXPECT_GT(one.separating.size(), 6u * n * n);
  for (const auto& [name, value] : one.statistics)
    EXPECT_EQ(two.statistics.at(name), value) << name;
  EXPECT_EQ(one.flags, two.flags);
  EXPECT_EQ(one.smallest, two.smallest);
  EXPECT_EQ(one.largest, two.largest);
  EXPECT_EQ(one.ratio, two.ratio);
  ASSERT_EQ(one.separating.size(), two.separating.size());
  for (std::size_t i = 0; i < one.separating.size(); ++i)
    EXPECT_TRUE(one.separating[i].tet == two.separating[i].tet && one.separating[i].opposite == two.separating[i].opposite &&
      one.separating[i].other == two.separating[i].other) << "face " << i;
}
