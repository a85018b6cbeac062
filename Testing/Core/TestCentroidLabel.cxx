// SPDX-License-Identifier: GPL-3.0-or-later
// Cells the optimisers leave across a boundary take the material they lie in (CentroidLabel.h,
// relabelCellsAcrossBoundaries), and the interfaces follow their new labels.
#include "BoxDomain.h"
#include "CentroidLabel.h"
#include "HierarchicalOracle.h"
#include "MeshTriangulation3.h"
#include "SphereDomain.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <random>

namespace
{
using namespace omesh;
using namespace omesh::cgal;
using C3t3 = MeshTriangulation3<CGAL::Sequential_tag>::C3t3;
using Tr = C3t3::Triangulation;

Vec3 centroid(const Tr::Cell_handle& c)
{
  Vec3 sum{ 0, 0, 0 };
  for (int i = 0; i < 4; ++i)
    sum = sum + toVec(c->vertex(i)->point().point());
  return 0.25 * sum;
}

double altitude(const Tr::Cell_handle& c)
{
  return smallestAltitude(toVec(c->vertex(0)->point().point()), toVec(c->vertex(1)->point().point()),
    toVec(c->vertex(2)->point().point()), toVec(c->vertex(3)->point().point()));
}
}

// A ball (material 1) in a housing (material 2), tetrahedralised from 60 points on its sphere,
// interface vertices but one (marked as inside a material: a point inside the ball would conflict
// with every cell of cospherical points); every cell labelled housing, as the exuder can label a
// cell it creates. The cells thicker than the facet distance with every vertex on the sphere
// become the ball's; the cells at the marked vertex and the thin ones keep their label; every face
// lies on an interface exactly where its two cells differ.
TEST(CentroidLabel, CellsAcrossABoundaryTakeTheMaterialTheyLieInAndTheInterfacesFollow)
{
  HierarchicalOracle oracle;
  oracle.add(std::make_shared<SphereDomain>(Vec3{ 0, 0, 0 }, 1.0, 1));
  oracle.add(std::make_shared<BoxDomain>(Vec3{ -3, -3, -3 }, Vec3{ 3, 3, 3 }, 2));
  C3t3 c3t3;
  Tr& tr = c3t3.triangulation();
  std::mt19937 random(5);
  std::normal_distribution<double> gauss;
  Tr::Vertex_handle inside;
  for (int k = 0; k < 60; ++k)
  {
    Vec3 p{ gauss(random), gauss(random), gauss(random) };
    p = (1.0 / norm(p)) * p;
    inside = tr.insert(Tr::Weighted_point(toPoint(p), 0.0));
    c3t3.set_dimension(inside, 2);
  }
  c3t3.set_dimension(inside, 3);
  const int housing = subdomainOf(2), ball = subdomainOf(1);
  for (auto c = tr.finite_cells_begin(); c != tr.finite_cells_end(); ++c)
    c3t3.add_to_complex(c, housing);
  for (auto f = tr.finite_facets_begin(); f != tr.finite_facets_end(); ++f)
    if (tr.is_infinite(f->first) || tr.is_infinite(f->first->neighbor(f->second)))
      c3t3.add_to_complex(*f, C3t3::Surface_patch_index(0, housing));

  const double facetDistance = 0.02;
  const size_t relabelled = relabelCellsAcrossBoundaries(c3t3, oracle, [&](int) { return facetDistance; });

  size_t thick = 0, thin = 0;
  for (auto c = tr.finite_cells_begin(); c != tr.finite_cells_end(); ++c)
  {
    ASSERT_LT(norm(centroid(c)), 1.0);
    const bool expected = !c->has_vertex(inside) && altitude(c) > facetDistance;
    EXPECT_EQ(c3t3.subdomain_index(c), expected ? ball : housing);
    (expected ? thick : thin) += 1;
  }
  EXPECT_EQ(relabelled, thick);
  EXPECT_GT(thick, 20u);
  EXPECT_GT(thin, 0u) << "the cells at the marked vertex";
  auto subdomain = [&](Tr::Cell_handle c) { return tr.is_infinite(c) ? 0 : c3t3.subdomain_index(c); };
  size_t interfaces = 0;
  for (auto f = tr.finite_facets_begin(); f != tr.finite_facets_end(); ++f)
  {
    const int a = subdomain(f->first), b = subdomain(f->first->neighbor(f->second));
    ASSERT_EQ(c3t3.is_in_complex(*f), a != b);
    if (a != b)
    {
      EXPECT_EQ(c3t3.surface_patch_index(*f), C3t3::Surface_patch_index(std::min(a, b), std::max(a, b)));
      ++interfaces;
    }
  }
  EXPECT_EQ(c3t3.number_of_facets_in_complex(), interfaces);
  EXPECT_EQ(relabelCellsAcrossBoundaries(c3t3, oracle, [&](int) { return facetDistance; }), 0u) << "nothing left";
}
