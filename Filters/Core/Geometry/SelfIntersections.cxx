// SPDX-License-Identifier: GPL-3.0-or-later
// CGAL's polygon-mesh-processing self-intersection test, kept out of the other translation units.
#include "SelfIntersections.h"

#include "InputError.h"
#include "OrientedTriangles.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>
#include <boost/property_map/function_property_map.hpp>

#include <algorithm>
#include <iterator>
#include <sstream>

namespace omesh
{
namespace
{
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = K::Point_3;
using Mesh = CGAL::Surface_mesh<Point>;
namespace PMP = CGAL::Polygon_mesh_processing;

Point toCgal(const Vec3& p) { return { p.x, p.y, p.z }; }

struct Enough
{
};

/// For triangles of the input that share vertices: do they meet anywhere else? (CGAL tests such
/// pairs combinatorially through the mesh, but orient_polygon_soup duplicates non-manifold
/// vertices, after which two solids welded at a corner would look like they intersect.)
bool meetBeyondSharedVertices(const TriangleSurface& s, int f, int g)
{
  const auto& a = s.triangles[f];
  const auto& b = s.triangles[g];
  std::vector<int> shared;
  for (int i : a)
    if (std::find(b.begin(), b.end(), i) != b.end())
      shared.push_back(i);
  const auto P = [&](int i) { return toCgal(s.points[i]); };
  const K::Triangle_3 ta(P(a[0]), P(a[1]), P(a[2])), tb(P(b[0]), P(b[1]), P(b[2]));
  if (shared.empty())
    return CGAL::do_intersect(ta, tb);
  auto other = [&](const std::array<int, 3>& t, std::vector<int> skip) {
    std::vector<int> rest;
    for (int i : t)
      if (std::find(skip.begin(), skip.end(), i) == skip.end())
        rest.push_back(i);
    return rest;
  };
  const std::vector<int> ra = other(a, shared), rb = other(b, shared);
  if (shared.size() == 1)
  {
    // they meet beyond the shared vertex iff an opposite edge meets the other triangle
    const K::Segment_3 ea(P(ra[0]), P(ra[1])), eb(P(rb[0]), P(rb[1]));
    return CGAL::do_intersect(ea, tb) || CGAL::do_intersect(eb, ta);
  }
  if (shared.size() == 2)
  {
    // a common edge: they overlap iff coplanar with both far corners on the same side
    const Point p = P(shared[0]), q = P(shared[1]), x = P(ra[0]), y = P(rb[0]);
    return CGAL::coplanar(p, q, x, y) && CGAL::coplanar_orientation(p, q, x, y) == CGAL::POSITIVE;
  }
  return true; // the same three vertices twice
}
}

std::vector<std::pair<int, int>> selfIntersections(const TriangleSurface& surface, size_t limit)
{
  // A halfedge mesh needs one orientation per edge; this duplicates non-manifold vertices (and
  // keeps the triangles in their order: face i is triangle i).
  return selfIntersections(surface, orientTriangles(surface), limit);
}

std::vector<std::pair<int, int>> selfIntersections(
  const TriangleSurface& surface, const OrientedTriangles& oriented, size_t limit)
{
  std::vector<std::pair<int, int>> pairs;
  if (!oriented.halfedgeMesh)
  {
    // CGAL cannot build a mesh of it; test the triangles pairwise through their boxes instead
    // (same exact predicates), which is what self_intersections does on a mesh.
    std::vector<CGAL::Box_intersection_d::Box_with_info_d<double, 3, int>> boxes;
    for (size_t t = 0; t < surface.triangles.size(); ++t)
    {
      const auto& tri = surface.triangles[t];
      CGAL::Bbox_3 b = toCgal(surface.points[tri[0]]).bbox() + toCgal(surface.points[tri[1]]).bbox() +
        toCgal(surface.points[tri[2]]).bbox();
      boxes.emplace_back(b, static_cast<int>(t));
    }
    try
    {
      CGAL::box_self_intersection_d(boxes.begin(), boxes.end(), [&](const auto& x, const auto& y) {
        if (meetBeyondSharedVertices(surface, x.info(), y.info()))
        {
          pairs.emplace_back(std::min(x.info(), y.info()), std::max(x.info(), y.info()));
          if (pairs.size() >= limit)
            throw Enough();
        }
      });
    }
    catch (const Enough&)
    {
    }
  }
  else
  {
    Mesh mesh;
    PMP::polygon_soup_to_polygon_mesh(oriented.surface.points, oriented.surface.triangles, mesh,
      CGAL::parameters::point_map(boost::make_function_property_map<Vec3>(&toCgal)));
    std::vector<std::pair<Mesh::Face_index, Mesh::Face_index>> found;
    try
    {
      // a counting iterator that stops CGAL after `limit` pairs (a surface fused with a copy of
      // itself has a pair for every triangle)
      struct Out
      {
        std::vector<std::pair<Mesh::Face_index, Mesh::Face_index>>* v;
        size_t limit;
        Out& operator*() { return *this; }
        Out& operator++() { return *this; }
        Out operator++(int) { return *this; }
        Out& operator=(const std::pair<Mesh::Face_index, Mesh::Face_index>& p)
        {
          v->push_back(p);
          if (v->size() >= limit)
            throw Enough();
          return *this;
        }
      };
      PMP::self_intersections(mesh, Out{ &found, std::max<size_t>(limit, 1) * 4 });
    }
    catch (const Enough&)
    {
    }
    for (const auto& [f, g] : found)
    {
      const int a = static_cast<int>(f.idx()), b = static_cast<int>(g.idx());
      if (meetBeyondSharedVertices(surface, a, b))
        pairs.emplace_back(std::min(a, b), std::max(a, b));
      if (pairs.size() >= limit)
        break;
    }
  }
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  return pairs;
}

std::string describeTriangle(const TriangleSurface& surface, int t)
{
  std::ostringstream o;
  o << "triangle " << t << " (";
  for (int k = 0; k < 3; ++k)
  {
    const Vec3& p = surface.points[surface.triangles[t][k]];
    o << (k ? ", " : "") << "(" << p.x << ", " << p.y << ", " << p.z << ")";
  }
  o << ")";
  return o.str();
}

void refuseSelfIntersections(const TriangleSurface& surface, const std::string& who)
{
  constexpr size_t kLimit = 1000;
  const auto pairs = selfIntersections(surface, kLimit);
  if (pairs.empty())
    return;
  std::ostringstream msg;
  msg << who << ": surface intersects itself: " << pairs.size() << (pairs.size() >= kLimit ? " or more" : "")
      << " pair(s) of triangles intersect; first: " << describeTriangle(surface, pairs[0].first) << " and "
      << describeTriangle(surface, pairs[0].second)
      << " (allow_self_intersections accepts it: where the surface overlaps itself the inside test decides)";
  throw InputError(msg.str());
}
}
