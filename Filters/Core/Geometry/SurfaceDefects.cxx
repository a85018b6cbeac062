// SPDX-License-Identifier: GPL-3.0-or-later
#include "SurfaceDefects.h"

#include "SelfIntersections.h"

#include <algorithm>
#include <cstdint>
#include <sstream>
#include <unordered_map>

namespace omesh
{
SurfaceDefects findSurfaceDefects(const TriangleSurface& surface, const OrientedTriangles& oriented, size_t pairLimit)
{
  SurfaceDefects d;
  std::unordered_map<uint64_t, int> edgeUse;
  edgeUse.reserve(surface.triangles.size() * 2);
  for (const auto& tri : surface.triangles)
    for (int e = 0; e < 3; ++e)
    {
      const auto lo = static_cast<uint64_t>(std::min(tri[e], tri[(e + 1) % 3]));
      const auto hi = static_cast<uint64_t>(std::max(tri[e], tri[(e + 1) % 3]));
      ++edgeUse[(lo << 32) | hi];
    }
  for (const auto& [key, uses] : edgeUse)
  {
    d.borderEdges += uses == 1;
    d.nonManifoldEdges += uses > 2;
  }
  if (d.borderEdges > 0)
    d.holes = surface.borderLoops();
  d.orientable = oriented.halfedgeMesh;
  d.intersectingPairs = selfIntersections(surface, oriented, pairLimit);
  d.moreIntersections = d.intersectingPairs.size() >= pairLimit;
  return d;
}

std::string SurfaceDefects::describe(const TriangleSurface& surface) const
{
  std::vector<std::string> parts;
  if (!holes.empty())
    parts.push_back(TriangleSurface::describeHoles(holes) +
      (2 * borderEdges > 3 * surface.triangles.size()
          ? " (most edges are on a border: pieces not welded? a larger merge tolerance welds them)"
          : ""));
  if (nonManifoldEdges > 0)
    parts.push_back(std::to_string(nonManifoldEdges) + " non-manifold edge(s) (used by more than two triangles)");
  if (!intersectingPairs.empty())
  {
    std::ostringstream o;
    o << intersectingPairs.size() << (moreIntersections ? " or more" : "")
      << " pair(s) of intersecting triangles; first: " << describeTriangle(surface, intersectingPairs[0].first)
      << " and " << describeTriangle(surface, intersectingPairs[0].second);
    parts.push_back(o.str());
  }
  if (!orientable)
    parts.push_back("no consistent orientation (non-orientable where pieces meet)");
  std::string text;
  for (const std::string& p : parts)
    text += (text.empty() ? "" : "; ") + p;
  return text;
}
}
