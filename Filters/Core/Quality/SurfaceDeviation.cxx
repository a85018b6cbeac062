// SPDX-License-Identifier: GPL-3.0-or-later
#include "SurfaceDeviation.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <cmath>
#include <sstream>

namespace omesh
{
namespace
{
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Triangle = K::Triangle_3;
using Primitive = CGAL::AABB_triangle_primitive<K, std::vector<Triangle>::const_iterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, Primitive>>;

K::Point_3 toCgal(const Vec3& p) { return { p.x, p.y, p.z }; }
}

std::string SurfaceDeviation::describe() const
{
  std::ostringstream o;
  o << "the mesh's boundary lies up to " << meshToInput << " from the input surface (at (" << meshToInputAt.x << ", "
    << meshToInputAt.y << ", " << meshToInputAt.z << ")), the input up to " << inputToMesh << " from the boundary (at ("
    << inputToMeshAt.x << ", " << inputToMeshAt.y << ", " << inputToMeshAt.z << "))";
  return o.str();
}

SurfaceDeviation surfaceDeviation(const TetMesh& mesh, int material, const SurfaceDomain& surface)
{
  SurfaceDeviation d;
  std::vector<Triangle> boundary;
  std::vector<char> onBoundary(mesh.points.size(), 0);
  for (size_t t = 0; t < mesh.interfaceTriangles.size(); ++t)
  {
    const auto& sides = mesh.interfaceMaterials[t];
    if ((sides[0] == material) == (sides[1] == material))
      continue;
    const auto& tri = mesh.interfaceTriangles[t];
    boundary.emplace_back(toCgal(mesh.points[tri[0]]), toCgal(mesh.points[tri[1]]), toCgal(mesh.points[tri[2]]));
    for (int v : tri)
      onBoundary[v] = 1;
  }
  d.boundaryTriangles = boundary.size();
  if (boundary.empty())
    return d;
  for (size_t v = 0; v < mesh.points.size(); ++v)
    if (onBoundary[v])
    {
      const double distance = surface.distanceToSurface(mesh.points[v]);
      if (distance > d.meshToInput)
      {
        d.meshToInput = distance;
        d.meshToInputAt = mesh.points[v];
      }
    }
  Tree tree(boundary.begin(), boundary.end());
  tree.accelerate_distance_queries();
  for (const Vec3& p : surface.surfacePoints())
  {
    const double distance = std::sqrt(tree.squared_distance(toCgal(p)));
    if (distance > d.inputToMesh)
    {
      d.inputToMesh = distance;
      d.inputToMeshAt = p;
    }
  }
  return d;
}
}
