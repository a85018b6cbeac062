// SPDX-License-Identifier: GPL-3.0-or-later
#include "OrientedTriangles.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>

namespace omesh
{
OrientedTriangles orientTriangles(const TriangleSurface& surface)
{
  using Point = CGAL::Exact_predicates_inexact_constructions_kernel::Point_3;
  namespace PMP = CGAL::Polygon_mesh_processing;
  std::vector<Point> points;
  points.reserve(surface.points.size());
  for (const auto& p : surface.points)
    points.push_back({ p.x, p.y, p.z });
  std::vector<std::vector<std::size_t>> polygons;
  polygons.reserve(surface.triangles.size());
  for (const auto& t : surface.triangles)
    polygons.push_back({ static_cast<std::size_t>(t[0]), static_cast<std::size_t>(t[1]), static_cast<std::size_t>(t[2]) });
  PMP::orient_polygon_soup(points, polygons);

  OrientedTriangles result;
  result.halfedgeMesh = PMP::is_polygon_soup_a_polygon_mesh(polygons);
  result.surface.points.reserve(points.size());
  for (const Point& p : points)
    result.surface.points.push_back({ p.x(), p.y(), p.z() });
  result.surface.triangles.reserve(polygons.size());
  for (const auto& poly : polygons)
    result.surface.triangles.push_back({ static_cast<int>(poly[0]), static_cast<int>(poly[1]), static_cast<int>(poly[2]) });
  return result;
}
}
