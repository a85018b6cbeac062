// SPDX-License-Identifier: GPL-3.0-or-later
#include "BoxDomain.h"
#include "HierarchicalOracle.h"
#include "MeshQuality.h"
#include "OracleMesher.h"
#include "QuadraticTets.h"
#include "SphereDomain.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>

using namespace omesh;

namespace
{
std::array<Vec3, 10> straightNodes(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d)
{
  std::array<Vec3, 10> x = { a, b, c, d };
  for (int e = 0; e < 6; ++e)
    x[4 + e] = 0.5 * (x[kQuadraticTetEdges[e][0]] + x[kQuadraticTetEdges[e][1]]);
  return x;
}

std::array<Vec3, 10> nodesOf(const QuadraticTetMesh& q, std::size_t t)
{
  std::array<Vec3, 10> x;
  for (int i = 0; i < 10; ++i)
    x[i] = q.points[q.tets[t][i]];
  return x;
}

/// A coarse mesh of the unit ball (material 1) over a box (material 2), no feature lines.
TetMesh ballOnBox(HierarchicalOracle& o)
{
  o.add(std::make_shared<SphereDomain>(Vec3{ 0, 0, 0 }, 1.0, 1));
  o.add(std::make_shared<BoxDomain>(Vec3{ -0.5, -0.5, -2 }, Vec3{ 0.5, 0.5, -0.5 }, 2));
  MesherOptions opt;
  opt.strategy = FeatureStrategy::None;
  opt.criteria.global.cellSize = opt.criteria.global.facetSize = 0.35;
  opt.criteria.global.facetDistance = 0.03;
  opt.seed = 3;
  return meshOracle(o, {}, {}, opt);
}
}

TEST(QuadraticTets, StraightTetrahedronHasConstantJacobianAndItsVolume)
{
  const auto x = straightNodes({ 0, 0, 0 }, { 2, 0, 0 }, { 0, 1, 0 }, { 0, 0, 3 });
  EXPECT_NEAR(quadraticTetJacobian(x, { 0.1, 0.2, 0.3, 0.4 }), 6.0, 1e-12);
  EXPECT_NEAR(quadraticTetJacobianRatio(x), 1.0, 1e-12);
  EXPECT_NEAR(quadraticTetVolume(x), 1.0, 1e-12);
}

TEST(QuadraticTets, BulgedEdgeChangesVolumeByTheQuadraticTerm)
{
  // A mid-edge node moved out of the tetrahedron: the exact (degree-3) volume against a midpoint
  // sum of det J over a fine grid of the reference tetrahedron.
  auto x = straightNodes({ 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 });
  x[4] = x[4] + Vec3{ 0, -0.1, -0.1 };
  double riemann = 0.0;
  const int n = 60;
  for (int i = 0; i < n; ++i)
    for (int j = 0; i + j < n; ++j)
      for (int k = 0; i + j + k < n; ++k)
      {
        const double l1 = (i + 0.5) / n, l2 = (j + 0.5) / n, l3 = (k + 0.5) / n;
        if (l1 + l2 + l3 >= 1.0)
          continue;
        riemann += quadraticTetJacobian(x, { 1.0 - l1 - l2 - l3, l1, l2, l3 });
      }
  riemann /= static_cast<double>(n) * n * n; // each cell has volume 1/n^3 of the unit cube
  EXPECT_NEAR(quadraticTetVolume(x), riemann, 0.01 * riemann);
  EXPECT_GT(quadraticTetVolume(x), 1.0 / 6.0);
}

TEST(QuadraticTets, InterfaceNodesLieOnTheSphereAndVolumesImprove)
{
  HierarchicalOracle o;
  const TetMesh m = ballOnBox(o);
  const QuadraticTetMesh q = makeQuadraticTets(m, o);
  ASSERT_EQ(q.tets.size(), m.tets.size());
  EXPECT_GT(q.statistics.at("quadratic.snapped_nodes"), 0);

  // Mid-edge nodes on the ball's free boundary (edges of faces between the ball and the outside,
  // away from the box) lie on the sphere; their straight midpoints do not.
  std::size_t checked = 0;
  double worstCurved = 0, worstStraight = 0;
  for (std::size_t t = 0; t < q.tets.size(); ++t)
    for (int e = 0; e < 6; ++e)
    {
      const Vec3& a = q.points[q.tets[t][kQuadraticTetEdges[e][0]]];
      const Vec3& b = q.points[q.tets[t][kQuadraticTetEdges[e][1]]];
      const Vec3& mid = q.points[q.tets[t][4 + e]];
      const bool onSphere = std::abs(norm(a) - 1) < 1e-9 && std::abs(norm(b) - 1) < 1e-9 && a.z > -0.4 && b.z > -0.4;
      if (!onSphere || m.tetMaterial[t] != 1 || q.pointDimension[q.tets[t][4 + e]] != 2)
        continue;
      ++checked;
      worstCurved = std::max(worstCurved, std::abs(norm(mid) - 1));
      worstStraight = std::max(worstStraight, std::abs(norm(0.5 * (a + b)) - 1));
    }
  ASSERT_GT(checked, 50u);
  EXPECT_GT(worstStraight, 1e-3);
  // relaxed nodes (if any) sit between; the others on the sphere up to the oracle's precision
  EXPECT_LT(worstCurved, 0.25 * worstStraight);

  double linear = 0, curved = 0;
  for (std::size_t t = 0; t < q.tets.size(); ++t)
  {
    const auto x = nodesOf(q, t);
    EXPECT_GE(quadraticTetJacobianRatio(x), QuadraticOptions{}.minJacobianRatio - 1e-12) << "tetrahedron " << t;
    if (m.tetMaterial[t] != 1)
      continue;
    linear += signedVolume(x[0], x[1], x[2], x[3]);
    curved += quadraticTetVolume(x);
  }
  const double exact = 4.0 / 3.0 * M_PI; // the ball has the higher priority: the box only adds
  EXPECT_LT(std::abs(curved - exact), 0.3 * std::abs(linear - exact))
    << "linear " << linear << " quadratic " << curved << " exact " << exact;
}

TEST(QuadraticTets, SameInputSameNodes)
{
  HierarchicalOracle o;
  const TetMesh m = ballOnBox(o);
  const QuadraticTetMesh a = makeQuadraticTets(m, o), b = makeQuadraticTets(m, o);
  ASSERT_EQ(a.points.size(), b.points.size());
  for (std::size_t i = 0; i < a.points.size(); ++i)
    ASSERT_EQ(norm(a.points[i] - b.points[i]), 0.0) << "point " << i;
  ASSERT_EQ(a.tets, b.tets);
}

TEST(QuadraticTets, TetrahedraBelowTheJacobianBoundAreRelaxed)
{
  // A box with a ball cut out: its concave boundary bends the curved faces into the tetrahedra.
  // A strict bound makes the relaxation work on many of them; every one must end above it.
  HierarchicalOracle o;
  auto ball = std::make_shared<SphereDomain>(Vec3{ 0, 0, 0 }, 1.0, 0);
  ball->setCut(true);
  o.add(ball);
  o.add(std::make_shared<BoxDomain>(Vec3{ -1.5, -1.5, -1.5 }, Vec3{ 1.5, 1.5, 1.5 }, 1));
  MesherOptions opt;
  opt.strategy = FeatureStrategy::None;
  opt.criteria.global.cellSize = opt.criteria.global.facetSize = 0.5;
  opt.criteria.global.facetDistance = 0.05;
  opt.seed = 3;
  const TetMesh m = meshOracle(o, {}, {}, opt);
  QuadraticOptions strict;
  strict.minJacobianRatio = 0.9;
  const QuadraticTetMesh q = makeQuadraticTets(m, o, strict);
  EXPECT_GT(q.statistics.at("quadratic.relaxed_nodes"), 0);
  EXPECT_GE(q.statistics.at("quadratic.min_jacobian_ratio"), strict.minJacobianRatio);
  for (std::size_t t = 0; t < q.tets.size(); ++t)
    ASSERT_GE(quadraticTetJacobianRatio(nodesOf(q, t)), strict.minJacobianRatio) << "tetrahedron " << t;
  // the default bound relaxes fewer nodes
  const QuadraticTetMesh loose = makeQuadraticTets(m, o);
  EXPECT_LT(loose.statistics.at("quadratic.relaxed_nodes"), q.statistics.at("quadratic.relaxed_nodes"));
  std::cout << "relaxed nodes: " << loose.statistics.at("quadratic.relaxed_nodes") << " of "
            << loose.statistics.at("quadratic.snapped_nodes") << " snapped (bound 0.9: "
            << q.statistics.at("quadratic.relaxed_nodes") << ")" << std::endl;
}
