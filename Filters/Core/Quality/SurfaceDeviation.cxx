// SPDX-License-Identifier: GPL-3.0-or-later
#include "SurfaceDeviation.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>
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

struct FaceHash
{
  size_t operator()(const std::array<int, 3>& f) const
  {
    return std::hash<uint64_t>()((static_cast<uint64_t>(f[0]) * 0x9E3779B97F4A7C15ull) ^
      (static_cast<uint64_t>(f[1]) << 21) ^ static_cast<uint64_t>(f[2]));
  }
};
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
  // the material's boundary from its tetrahedra: their faces that no other tetrahedron of the
  // material shares (what a user's viewer shows, whatever the mesher's own interface list holds)
  std::unordered_map<std::array<int, 3>, int, FaceHash> faces; // sorted corners -> times seen
  for (size_t t = 0; t < mesh.tets.size(); ++t)
  {
    if (mesh.tetMaterial[t] != material)
      continue;
    const auto& tet = mesh.tets[t];
    for (int i = 0; i < 4; ++i)
    {
      std::array<int, 3> f{ tet[(i + 1) & 3], tet[(i + 2) & 3], tet[(i + 3) & 3] };
      std::sort(f.begin(), f.end());
      ++faces[f];
    }
  }
  std::vector<Triangle> boundary;
  std::vector<char> onBoundary(mesh.points.size(), 0);
  for (const auto& [f, times] : faces)
  {
    if (times != 1)
      continue;
    boundary.emplace_back(toCgal(mesh.points[f[0]]), toCgal(mesh.points[f[1]]), toCgal(mesh.points[f[2]]));
    for (int v : f)
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
