// SPDX-License-Identifier: GPL-3.0-or-later
#include "SeamWelding.h"

#include "SeamPairs.h"
#include "UnionFind.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace omesh
{
std::string SeamWelding::describe() const
{
  std::ostringstream o;
  o << "welded " << pairedEdges << " unwelded seam edge(s) (of " << borderEdges << " border edges): " << mergedPoints
    << " point(s) merged, moved by at most " << largestMove << " (gaps up to " << widestGap << ")";
  return o.str();
}

namespace
{
/// Per group root, whether its points stay apart: merged into their mean, one would move beyond
/// `limit` or twice the group's widest seam gap (copies of one point lie within a gap or two of
/// each other), or a triangle would fold.
std::vector<char> groupsKeptApart(const TriangleSurface& surface, const std::vector<std::array<int, 2>>& border,
  const std::vector<SeamPair>& pairs, UnionFind& groups, const std::vector<Vec3>& sum, const std::vector<int>& size,
  double limit)
{
  const size_t n = surface.points.size();
  std::vector<double> groupGap(n, 0.0);
  for (const SeamPair& p : pairs)
    for (int v : border[p.first])
    {
      const size_t g = groups.find(v);
      groupGap[g] = std::max(groupGap[g], p.gap);
    }
  std::vector<char> keepApart(n, 0);
  for (size_t v = 0; v < n; ++v)
  {
    const size_t g = groups.find(v);
    const double move = norm(surface.points[v] - (1.0 / size[g]) * sum[g]);
    if (size[g] > 1 && !(move <= limit && move <= 2.0 * groupGap[g]))
      keepApart[g] = 1;
  }
  for (const auto& t : surface.triangles)
    for (int k = 0; k < 3; ++k)
    {
      const size_t g = groups.find(t[k]);
      if (g == groups.find(t[(k + 1) % 3]))
        keepApart[g] = 1;
    }
  return keepApart;
}
}

std::string seamWeldWarning(const std::string& name, const std::string& description)
{
  return name + ": " + description + " (a triangle soup, or copies of points not merged?); the mesh follows the welded surface";
}

SeamWelding weldSeams(const TriangleSurface& surface, double limit)
{
  SeamWelding out;
  const std::vector<std::array<int, 2>> border = surface.borderEdges();
  out.borderEdges = border.size();
  const size_t n = surface.points.size();
  UnionFind groups(n);
  std::vector<SeamPair> pairs = pairSeams(surface.points, border, false, true);
  pairs.erase(std::remove_if(pairs.begin(), pairs.end(), [&](const SeamPair& p) { return !(p.gap <= limit); }), pairs.end());
  for (const SeamPair& p : pairs)
  {
    const auto &e = border[p.first], &f = border[p.second];
    groups.join(e[0], f[p.reversed ? 1 : 0]);
    groups.join(e[1], f[p.reversed ? 0 : 1]);
  }
  std::vector<Vec3> sum(n);
  std::vector<int> size(n, 0);
  for (size_t v = 0; v < n; ++v)
  {
    const size_t g = groups.find(v);
    sum[g] = sum[g] + surface.points[v];
    ++size[g];
  }
  const std::vector<char> keepApart = groupsKeptApart(surface, border, pairs, groups, sum, size, limit);
  // new indices: a merged group becomes one point where its first member was
  std::vector<int> index(n, -1), groupIndex(n, -1);
  for (size_t v = 0; v < n; ++v)
  {
    const size_t g = groups.find(v);
    const bool merged = size[g] > 1 && !keepApart[g];
    if (!merged)
    {
      index[v] = static_cast<int>(out.surface.points.size());
      out.surface.points.push_back(surface.points[v]);
      continue;
    }
    const Vec3 mean = (1.0 / size[g]) * sum[g];
    out.largestMove = std::max(out.largestMove, norm(surface.points[v] - mean));
    if (groupIndex[g] < 0)
    {
      groupIndex[g] = static_cast<int>(out.surface.points.size());
      out.surface.points.push_back(mean);
    }
    else
      ++out.mergedPoints;
    index[v] = groupIndex[g];
  }
  out.pointIndex = index;
  out.surface.triangles.reserve(surface.triangles.size());
  for (const auto& t : surface.triangles)
    out.surface.triangles.push_back({ index[t[0]], index[t[1]], index[t[2]] });
  for (const SeamPair& p : pairs)
  {
    const size_t g = groups.find(border[p.first][0]);
    if (size[g] > 1 && !keepApart[g] && !keepApart[groups.find(border[p.first][1])])
    {
      out.pairedEdges += 2;
      out.widestGap = std::max(out.widestGap, p.gap);
    }
  }
  return out;
}
}
