// SPDX-License-Identifier: GPL-3.0-or-later
// The mesher's three-point weighted circumcentre (MeshTriangulation3.h, AccurateWeightedCircumcenter):
// the same points as CGAL's robust construction, which it skips only where doubles show its predicate.
#include "MeshTriangulation3.h"

#include <gtest/gtest.h>

#include <random>

namespace
{
using omesh::cgal::AccurateWeightedCircumcenter;
using omesh::cgal::K;
using Robust = AccurateWeightedCircumcenter::Base;

K::Weighted_point_3 at(double x, double y, double z, double w = 0.0) { return { K::Point_3(x, y, z), w }; }

/// Every coordinate to the bit, and how often the doubles decided.
void expectSameAsCgal(const std::vector<std::array<K::Weighted_point_3, 3>>& triangles, int& certified)
{
  const AccurateWeightedCircumcenter mine{ K() };
  const Robust cgal{ K() };
  for (const auto& t : triangles)
  {
    const K::Point_3 a = mine(t[0], t[1], t[2]), b = cgal(t[0], t[1], t[2]);
    ASSERT_EQ(a.x(), b.x());
    ASSERT_EQ(a.y(), b.y());
    ASSERT_EQ(a.z(), b.z());
    certified += AccurateWeightedCircumcenter::certainlyInsideEquatorSphere(t[0].point(), t[1].point(), t[2].point(), a);
  }
}
}

TEST(WeightedCircumcenter, ThreePointsAreCgalsRobustOnes)
{
  std::mt19937 rng(12);
  std::uniform_real_distribution<double> u(-50.0, 50.0), small(-1e-9, 1e-9);
  std::vector<std::array<K::Weighted_point_3, 3>> shaped, thin;
  for (int i = 0; i < 20000; ++i)
  {
    shaped.push_back({ at(u(rng), u(rng), u(rng)), at(u(rng), u(rng), u(rng)), at(u(rng), u(rng), u(rng)) });
    // nearly collinear: r a hair off the line pq (the flat facets the predicate is there for)
    const K::Point_3 p(u(rng), u(rng), u(rng)), q(u(rng), u(rng), u(rng));
    const double s = std::uniform_real_distribution<double>(0.0, 1.0)(rng);
    thin.push_back({ K::Weighted_point_3(p, 0.0), K::Weighted_point_3(q, 0.0),
      at(p.x() + s * (q.x() - p.x()) + small(rng), p.y() + s * (q.y() - p.y()) + small(rng),
        p.z() + s * (q.z() - p.z()) + small(rng)) });
  }
  // weighted (protecting balls): CGAL's construction
  std::vector<std::array<K::Weighted_point_3, 3>> weighted{ { at(0, 0, 0, 1), at(4, 0, 0, 0.5), at(0, 3, 0) } };
  int certified = 0;
  expectSameAsCgal(shaped, certified);
  EXPECT_GT(certified, 19000); // the doubles decide almost every well-shaped facet
  int thinCertified = 0;
  expectSameAsCgal(thin, thinCertified);
  EXPECT_LT(thinCertified, 1000); // and leave the nearly flat ones to CGAL
  expectSameAsCgal(weighted, certified);
}
