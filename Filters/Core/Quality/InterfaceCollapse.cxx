// SPDX-License-Identifier: GPL-3.0-or-later
#include "InterfaceCollapse.h"

#include "MeshQuality.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <utility>

namespace omesh
{
namespace
{
/// Without facet distances, the interface may move by this share of the collapsed edge.
constexpr double kReachOfEdge = 0.05;
/// A collapse may leave tetrahedra up to this times their cell size (circumradius): merging a
/// vertex lengthens the edges around it, and at a tight cell size no collapse would remain for a
/// tetrahedron that stays below the angle window otherwise.
constexpr double kCollapseSizeSlack = 1.5;

std::array<int, 3> withFor(std::array<int, 3> tri, int from, int to)
{
  for (int& v : tri)
    if (v == from)
      v = to;
  return tri;
}

bool holds(const std::array<int, 3>& tri, int v)
{
  return tri[0] == v || tri[1] == v || tri[2] == v;
}

/// Distance from x to triangle abc's plane, or infinity for a degenerate triangle.
double planeDistance(const Vec3& x, const Vec3& a, const Vec3& b, const Vec3& c)
{
  const Vec3 n = cross(b - a, c - a);
  const double area = norm(n);
  return area > 0 ? std::abs(dot(x - a, n)) / area : HUGE_VAL;
}
}

InterfaceCollapse::InterfaceCollapse(ImprovementMesh& state)
  : state_(state)
  , mesh_(state.mesh())
  , stars_(state.stars())
{
}

bool InterfaceCollapse::collapseAround(int t)
{
  const auto q = stars_.tet(t);
  int bestC = -1, bestU = -1;
  double best = -1.0;
  for (int c : q)
  {
    if (state_.kind(c) != VertexKind::Interface || mesh_.pointDimension[static_cast<std::size_t>(c)] != 2)
      continue;
    const double now = state_.starQuality(c);
    std::set<int> neighbours; // on c's interface
    for (int k : state_.interfacesAt(c))
      for (int v : mesh_.interfaceTriangles[static_cast<std::size_t>(k)])
        if (v != c)
          neighbours.insert(v);
    for (int u : neighbours)
    {
      const double after = evaluate(c, u);
      if (after > std::max(best, now + 1e-9))
      {
        best = after;
        bestC = c;
        bestU = u;
      }
    }
  }
  if (bestC < 0)
    return false;
  apply(bestC, bestU);
  return true;
}

bool InterfaceCollapse::collapse(int c, int u)
{
  if (state_.kind(c) != VertexKind::Interface || mesh_.pointDimension[static_cast<std::size_t>(c)] != 2 ||
    !(evaluate(c, u) > 0))
    return false;
  apply(c, u);
  return true;
}

double InterfaceCollapse::evaluate(int c, int u) const
{
  const auto& sides = state_.sides(c);
  if (sides[0] < 0 || sides[1] < 0) // on the outer boundary: the link condition would need its outside
    return -1.0;
  const auto& star = stars_.star(c);
  for (int t : star)
  {
    const auto& q = stars_.tet(t);
    for (int i = 0; i < 4; ++i)
    {
      if (q[i] == c)
        continue;
      // the face opposite q[i] holds c: another tetrahedron beyond it (a closed star)
      const std::array<int, 3> f{ q[(i + 1) & 3], q[(i + 2) & 3], q[(i + 3) & 3] };
      if (stars_.beyond(t, f[0], f[1], f[2]) < 0)
        return -1.0;
      for (int v : f)
        if (v != c && state_.isKept(c, v))
          return -1.0;
    }
  }
  if (stars_.around(c, u).empty() || !linkCondition(c, u))
    return -1.0;
  const auto& dOf = state_.options().facetDistanceOf;
  double reach = HUGE_VAL;
  for (int m : sides)
    if (dOf && dOf(m) > 0)
      reach = std::min(reach, dOf(m));
  if (!std::isfinite(reach))
    reach = kReachOfEdge * norm(mesh_.points[static_cast<std::size_t>(c)] - mesh_.points[static_cast<std::size_t>(u)]);
  if (!interfaceKept(c, u, reach))
    return -1.0;
  // the new tetrahedra: positive, no flaw their originals did not have (a collapse may leave a
  // tetrahedron as large or short as before, never across a boundary), at most
  // kCollapseSizeSlack x their cell size
  double worst = HUGE_VAL;
  for (const auto& [t, q] : replacedStar(c, u))
  {
    const int material = stars_.material(t);
    const unsigned before = state_.flaws(stars_.tet(t), material);
    const double quality = state_.quality(q);
    if (!(quality > 0) || (state_.flaws(q, material, kCollapseSizeSlack) & ~state_.tolerableFlaws(before)) != 0)
      return -1.0;
    worst = std::min(worst, quality);
  }
  return std::isfinite(worst) ? worst : -1.0;
}

std::vector<std::pair<int, std::array<int, 4>>> InterfaceCollapse::replacedStar(int c, int u) const
{
  std::vector<std::pair<int, std::array<int, 4>>> out;
  for (int t : stars_.star(c))
  {
    std::array<int, 4> q = stars_.tet(t);
    if (std::find(q.begin(), q.end(), u) != q.end())
      continue; // around the collapsed edge: it goes
    std::replace(q.begin(), q.end(), c, u);
    out.emplace_back(t, q);
  }
  return out;
}

bool InterfaceCollapse::linkCondition(int c, int u) const
{
  // the link of a vertex: the faces opposite it in its tetrahedra; of an edge: the opposite edges
  auto linkOf = [this](int v, std::set<int>& vertices, std::set<std::uint64_t>& edges) {
    for (int t : stars_.star(v))
    {
      std::array<int, 3> f{};
      int k = 0;
      for (int w : stars_.tet(t))
        if (w != v)
          f[static_cast<std::size_t>(k++)] = w;
      for (int i = 0; i < 3; ++i)
      {
        vertices.insert(f[static_cast<std::size_t>(i)]);
        edges.insert(edgeKey(f[static_cast<std::size_t>(i)], f[static_cast<std::size_t>((i + 1) % 3)]));
      }
    }
  };
  std::set<int> vc, vu, ve;
  std::set<std::uint64_t> ec, eu, ee;
  linkOf(c, vc, ec);
  linkOf(u, vu, eu);
  for (int t : stars_.around(c, u))
  {
    std::array<int, 2> e{};
    int k = 0;
    for (int w : stars_.tet(t))
      if (w != c && w != u)
        e[static_cast<std::size_t>(k++)] = w;
    ve.insert(e[0]);
    ve.insert(e[1]);
    ee.insert(edgeKey(e[0], e[1]));
  }
  std::vector<int> sharedVertices;
  std::set_intersection(vc.begin(), vc.end(), vu.begin(), vu.end(), std::back_inserter(sharedVertices));
  sharedVertices.erase(std::remove_if(sharedVertices.begin(), sharedVertices.end(), [&](int w) { return w == c || w == u; }),
    sharedVertices.end());
  std::vector<std::uint64_t> sharedEdges;
  std::set_intersection(ec.begin(), ec.end(), eu.begin(), eu.end(), std::back_inserter(sharedEdges));
  const auto touchesEdge = [&](std::uint64_t e) {
    const int lo = static_cast<int>(e & 0xffffffffu), hi = static_cast<int>(e >> 32);
    return lo == c || lo == u || hi == c || hi == u;
  };
  sharedEdges.erase(std::remove_if(sharedEdges.begin(), sharedEdges.end(), touchesEdge), sharedEdges.end());
  return std::equal(sharedVertices.begin(), sharedVertices.end(), ve.begin(), ve.end()) &&
    std::equal(sharedEdges.begin(), sharedEdges.end(), ee.begin(), ee.end());
}

bool InterfaceCollapse::interfaceKept(int c, int u, double reach) const
{
  const Vec3& x = mesh_.points[static_cast<std::size_t>(c)];
  double nearest = HUGE_VAL;
  for (int k : state_.interfacesAt(c))
  {
    const auto& tri = mesh_.interfaceTriangles[static_cast<std::size_t>(k)];
    if (holds(tri, u))
      continue;
    const auto moved = withFor(tri, c, u);
    if (state_.isInterface(moved[0], moved[1], moved[2]))
      return false;
    const auto& p = mesh_.points;
    nearest = std::min(nearest,
      planeDistance(x, p[static_cast<std::size_t>(moved[0])], p[static_cast<std::size_t>(moved[1])], p[static_cast<std::size_t>(moved[2])]));
  }
  return nearest <= reach;
}

void InterfaceCollapse::apply(int c, int u)
{
  std::vector<Retriangulated> changes;
  for (int k : state_.interfacesAt(c))
  {
    const auto& tri = mesh_.interfaceTriangles[static_cast<std::size_t>(k)];
    const auto& materials = mesh_.interfaceMaterials[static_cast<std::size_t>(k)];
    changes.push_back({ tri, materials, true });
    if (!holds(tri, u))
      changes.push_back({ withFor(tri, c, u), materials, false });
  }
  const std::vector<std::pair<int, std::array<int, 4>>> made = replacedStar(c, u);
  const std::vector<int> old = stars_.star(c);
  for (int t : old)
    stars_.remove(t);
  for (const auto& [t, q] : made)
    state_.addTet(q, stars_.material(t));
  state_.swapInterfaces(changes);
  state_.dropVertex(c);
  const auto& around = stars_.star(u);
  state_.touched().insert(state_.touched().end(), around.begin(), around.end());
  ++state_.report().interfaceCollapses;
}
}
