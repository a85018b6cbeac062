// SPDX-License-Identifier: GPL-3.0-or-later
// The mesher's three- and four-point weighted circumcentres (MeshTriangulation3.h, AccurateWeightedCircumcenter):
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

TEST(WeightedCircumcenter, FourPointsAreCgalsRobustOnes)
{
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> u(-50.0, 50.0), unit(0.0, 1.0), small(-1e-9, 1e-9);
  auto point = [&] { return K::Point_3(u(rng), u(rng), u(rng)); };
  std::vector<std::array<K::Point_3, 4>> shaped, flat;
  for (int i = 0; i < 20000; ++i)
  {
    shaped.push_back({ point(), point(), point(), point() });
    // nearly flat: s a hair off the plane of pqr (the cells the predicate is there for)
    const K::Point_3 p = point(), q = point(), r = point();
    const double a = unit(rng), b = unit(rng) * (1.0 - a);
    flat.push_back({ p, q, r,
      K::Point_3(p.x() + a * (q.x() - p.x()) + b * (r.x() - p.x()) + small(rng),
        p.y() + a * (q.y() - p.y()) + b * (r.y() - p.y()) + small(rng),
        p.z() + a * (q.z() - p.z()) + b * (r.z() - p.z()) + small(rng)) });
  }
  const AccurateWeightedCircumcenter mine{ K() };
  const Robust cgal{ K() };
  auto den = [](const std::array<K::Point_3, 4>& c) { // det(q - p, r - p, s - p), as CGAL computes it
    double nx, ny, nz, d;
    CGAL::determinants_for_circumcenterC3(c[0].x(), c[0].y(), c[0].z(), c[1].x(), c[1].y(), c[1].z(), c[2].x(),
      c[2].y(), c[2].z(), c[3].x(), c[3].y(), c[3].z(), nx, ny, nz, d);
    return d;
  };
  // cells are positively oriented (CGAL's precondition): swap two points where they are not
  auto check = [&](std::vector<std::array<K::Point_3, 4>>& cells) {
    int certified = 0;
    for (auto& c : cells)
    {
      const CGAL::Orientation o = CGAL::orientation(c[0], c[1], c[2], c[3]);
      if (o == CGAL::COPLANAR)
        continue;
      if (o == CGAL::NEGATIVE)
        std::swap(c[0], c[1]);
      const K::Weighted_point_3 p(c[0], 0.0), q(c[1], 0.0), r(c[2], 0.0), s(c[3], 0.0);
      const K::Point_3 a = mine(p, q, r, s), b = cgal(p, q, r, s);
      EXPECT_EQ(a.x(), b.x());
      EXPECT_EQ(a.y(), b.y());
      EXPECT_EQ(a.z(), b.z());
      certified += AccurateWeightedCircumcenter::certainlyInsideCircumsphere(c[0], c[1], c[2], c[3], den(c), a);
    }
    return certified;
  };
  EXPECT_GT(check(shaped), 19000); // the doubles decide almost every cell
  EXPECT_LT(check(flat), 1000);    // and leave the nearly flat ones to CGAL
  // a negative orientation is never certified (CGAL's predicate would answer the other side)
  const K::Point_3 p(0, 0, 0), q(1, 0, 0), r(0, 1, 0), s(0, 0, 1), centre(0.5, 0.5, 0.5);
  ASSERT_EQ(CGAL::orientation(p, q, r, s), CGAL::POSITIVE);
  EXPECT_TRUE(AccurateWeightedCircumcenter::certainlyInsideCircumsphere(p, q, r, s, den({ p, q, r, s }), centre));
  EXPECT_FALSE(AccurateWeightedCircumcenter::certainlyInsideCircumsphere(q, p, r, s, den({ q, p, r, s }), centre));
  // nor a point outside the sphere
  EXPECT_FALSE(AccurateWeightedCircumcenter::certainlyInsideCircumsphere(p, q, r, s, den({ p, q, r, s }), K::Point_3(3, 3, 3)));
}
