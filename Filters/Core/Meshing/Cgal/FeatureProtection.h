// SPDX-License-Identifier: GPL-3.0-or-later
// Private to Meshing/OracleMesher.cxx (the sequential Mesh_3 translation unit): CGAL's protection
// of the feature lines: the polylines it protects and its stoppable edge size.
#pragma once

#include "FeatureSegments.h"
#include "OracleMeshDomain.h"
#include "SequentialTypes.h"

#include <array>
#include <atomic>
#include <map>
#include <memory>
#include <vector>

namespace omesh::cgal::sequential
{
/// Thrown inside CGAL's feature protection (its worker thread) once it was asked to stop.
struct ProtectionStopped
{
};

/// The edge size of CGAL's feature protection, reading the stop flag too: CGAL reads its own flag
/// only between passes, and one pass took minutes (148 s past a 20 s time limit, balls on feature
/// lines meeting at 1 degree), while it asks the size at every ball it places or checks.
/// Per polyline (the per-feature level): a ball on curve c takes that curve's size, a corner ball
/// the finest of the curves that meet there; `size` elsewhere (and for every ball when no curve
/// has its own: the meshes of before).
struct StoppableEdgeSize
{
  double size;
  const std::atomic<bool>* stop;
  const MeshDomain* domain = nullptr;
  std::shared_ptr<const std::vector<double>> curveSizes;                    ///< of curve index c at c - 1
  std::shared_ptr<const std::map<std::array<double, 3>, double>> cornerSizes; ///< by the corner's coordinates
  double operator()(const K::Point_3& p, int dim, const MeshDomain::Index& index) const
  {
    if (stop->load(std::memory_order_relaxed))
      throw ProtectionStopped{};
    if (!curveSizes)
      return size;
    if (dim == 1 || dim == -2)
    {
      const int c = domain->curve_index(index);
      if (c >= 1 && static_cast<size_t>(c) <= curveSizes->size())
        return (*curveSizes)[c - 1];
    }
    else if (dim == 0 || dim == -1)
    {
      const auto it = cornerSizes->find({ p.x(), p.y(), p.z() });
      if (it != cornerSizes->end())
        return it->second;
    }
    return size;
  }
};

/// Maximal polylines through the segments, broken at points of degree != 2 and wherever the line
/// turns by more than kStraightTurn: CGAL protects a polyline as one smooth curve, its mesh edges
/// join consecutive ball centres, and such a chord cuts every input point between them (broken at
/// bends past 20 degrees only, the found lines' small turns left 7-19 % of the lines' length off
/// the generated bone/implant meshes with Both, the demo's rounded edges 11 %). As a polyline's
/// end a bend becomes a protected corner, a mesh vertex. Points on a straight line (a found
/// curve's crossings of a label map's cell planes) stay inside: a chord through them lies on the
/// line (featureCoverage counts it, within 1e-6 of the edge's length) and a corner there would
/// only shrink the balls.
constexpr double kStraightTurn = 1e-7; // radians: a chord's distance to the point < 1e-7 x its length

/// The polylines for CGAL, each with one edge size: they also break where the segments' resolved
/// edge sizes (`sizes`, one per segment) differ.
struct Polylines
{
  std::vector<std::vector<K::Point_3>> lines;
  std::vector<double> sizes; ///< of lines[k], the edge size of its segments
};

inline Polylines toPolylines(const FeatureSegments& f, const std::vector<double>& sizes)
{
  std::vector<std::vector<size_t>> inc(f.points.size());
  for (size_t s = 0; s < f.segments.size(); ++s)
  {
    inc[f.segments[s][0]].push_back(s);
    inc[f.segments[s][1]].push_back(s);
  }
  auto other = [&](size_t s, size_t p) { return f.segments[s][0] == static_cast<int>(p) ? f.segments[s][1] : f.segments[s][0]; };
  std::vector<char> breaks(f.points.size(), 0);
  for (size_t p = 0; p < f.points.size(); ++p)
  {
    if (inc[p].size() != 2)
    {
      breaks[p] = 1;
      continue;
    }
    const Vec3 in = f.points[p] - f.points[other(inc[p][0], p)], out = f.points[other(inc[p][1], p)] - f.points[p];
    const bool straight = dot(in, out) > 0 && norm(cross(in, out)) <= kStraightTurn * norm(in) * norm(out);
    breaks[p] = !straight || sizes[inc[p][0]] != sizes[inc[p][1]];
  }
  std::vector<char> used(f.segments.size(), 0);
  Polylines lines;
  auto walk = [&](int start, size_t first) {
    std::vector<K::Point_3> line{ toPoint(f.points[start]) };
    int at = start;
    size_t s = first;
    while (true)
    {
      used[s] = 1;
      at = other(s, static_cast<size_t>(at));
      line.push_back(toPoint(f.points[at]));
      if (breaks[at])
        break;
      const size_t next = inc[at][0] == s ? inc[at][1] : inc[at][0];
      if (used[next])
        break;
      s = next;
    }
    lines.lines.push_back(std::move(line));
    lines.sizes.push_back(sizes[first]);
  };
  for (size_t p = 0; p < f.points.size(); ++p)
    if (breaks[p])
      for (size_t s : inc[p])
        if (!used[s])
          walk(static_cast<int>(p), s);
  for (size_t s = 0; s < f.segments.size(); ++s) // closed loops without a break
    if (!used[s])
      walk(f.segments[s][0], s);
  return lines;
}
}
