// SPDX-License-Identifier: GPL-3.0-or-later
#include "SliverPeeler.h"

#include "MeshQuality.h"

#include <algorithm>

namespace omesh
{
namespace
{
/// A tetrahedron is peeled only when its height is below this x its longest edge: the interface
/// moves by no more than that.
constexpr double kPeelHeight = 0.2;
}

SliverPeeler::SliverPeeler(ImprovementMesh& state, TetFlips& flips, VertexMover& mover)
  : state_(state)
  , flips_(flips)
  , mover_(mover)
  , mesh_(state.mesh())
  , stars_(state.stars())
{
}

bool SliverPeeler::peel(int t)
{
  const auto q = stars_.tet(t);
  const int m = stars_.material(t);
  const auto& p = mesh_.points;
  for (int v : q)
    if (mesh_.pointDimension[static_cast<std::size_t>(v)] > 2)
      return false;
  if (!(smallestAltitude(p[q[0]], p[q[1]], p[q[2]], p[q[3]]) <= kPeelHeight * state_.longestEdge(q)))
    return false;
  std::array<int, 4> side; // the material beyond the face opposite q[f], -1 outside
  for (int f = 0; f < 4; ++f)
  {
    const auto [a, b, c] = face(q, f);
    const int next = stars_.beyond(t, a, b, c);
    side[f] = next < 0 ? -1 : stars_.material(next);
    if (state_.isInterface(a, b, c) != (side[f] != m))
      return false; // an interface that does not separate materials here: not ours to move
  }
  for (int f = 0; f < 4; ++f)
    for (int g = f + 1; g < 4; ++g)
    {
      // faces f and g towards x, the other two not
      const int x = side[f];
      int k1 = -1, k2 = -1;
      for (int e = 0; e < 4; ++e)
        if (e != f && e != g)
          (k1 < 0 ? k1 : k2) = e;
      if (x == m || side[g] != x || side[k1] == x || side[k2] == x)
        continue;
      const int a = q[k1], b = q[k2]; // the fold edge, shared by faces f and g
      const int c = q[f], d = q[g];   // shared by the other two faces
      // the other two faces towards t's own material: edge cd stays inside it (no pinch);
      // removed: cd must not be on the boundary already (no non-manifold edge)
      if (state_.isKept(a, b) || (side[k1] == m && side[k2] == m && !insideOneMaterial(c, d, m)) ||
        (x < 0 && !closedAround(c, d)))
        continue;
      std::vector<Retriangulated> changes;
      for (int e : { f, g })
        changes.push_back({ face(q, e), { 0, 0 }, true });
      for (int e : { k1, k2 })
        changes.push_back({ face(q, e), { x, side[e] }, false });
      if (x < 0 ? removeToOutside(t, changes) : giveTo(t, x, a, b, changes))
        return true;
    }
  return false;
}

std::array<int, 3> SliverPeeler::face(const std::array<int, 4>& q, int f)
{
  return { q[(f + 1) & 3], q[(f + 2) & 3], q[(f + 3) & 3] };
}

bool SliverPeeler::insideOneMaterial(int c, int d, int m) const
{
  const auto around = stars_.around(c, d);
  for (int u : around)
  {
    if (stars_.material(u) != m)
      return false;
    for (int v : stars_.tet(u))
      if (v != c && v != d && state_.isInterface(c, d, v))
        return false;
  }
  return !around.empty() && closedAround(c, d);
}

bool SliverPeeler::closedAround(int c, int d) const
{
  for (int u : stars_.around(c, d))
    for (int v : stars_.tet(u))
      if (v != c && v != d && stars_.beyond(u, c, d, v) < 0)
        return false;
  return true;
}

bool SliverPeeler::removeToOutside(int t, std::vector<Retriangulated>& changes)
{
  for (int v : stars_.tet(t))
    if (stars_.star(v).size() < 2)
      return false;
  stars_.remove(t);
  state_.swapInterfaces(changes);
  for (int v : stars_.tet(t)) // a removed tetrahedron keeps its vertices
    state_.touched().insert(state_.touched().end(), stars_.star(v).begin(), stars_.star(v).end());
  ++state_.report().peeled;
  return true;
}

bool SliverPeeler::giveTo(int t, int x, int a, int b, std::vector<Retriangulated>& changes)
{
  const int m = stars_.material(t);
  const double before = state_.quality(t);
  stars_.setMaterial(t, x);
  const auto undo = state_.swapInterfaces(changes);
  const auto q = stars_.tet(t);
  bool done = false;
  for (int i = 0; i < 4 && !done; ++i)
    for (int j = i + 1; j < 4 && !done; ++j)
      done = flips_.removeEdge(q[i], q[j]);
  for (int f = 0; f < 4 && !done; ++f)
    done = flips_.removeFace(t, f);
  if (!done)
    done = removeEdgeAndMove(a, b, before);
  if (done)
  {
    ++state_.report().peeled;
    return true;
  }
  stars_.setMaterial(t, m);
  state_.undoSwap(undo);
  return false;
}

bool SliverPeeler::removeEdgeAndMove(int a, int b, double before)
{
  std::vector<int> made, old;
  const auto report = state_.report();
  const std::size_t touched = state_.touched().size();
  if (!flips_.removeEdge(a, b, &made, &old))
    return false;
  std::vector<std::pair<int, Vec3>> positions;
  for (int t : made)
    for (int v : stars_.tet(t))
      if (v != a && v != b && std::none_of(positions.begin(), positions.end(), [&](const auto& e) { return e.first == v; }))
        positions.emplace_back(v, mesh_.points[static_cast<std::size_t>(v)]);
  for (const auto& [v, at] : positions)
    mover_.moveVertex(v);
  if (state_.worstOf(made) > before + 1e-9)
    return true;
  for (const auto& [v, at] : positions)
    mesh_.points[static_cast<std::size_t>(v)] = at;
  for (int t : made)
    stars_.remove(t);
  for (int t : old)
    stars_.revive(t);
  state_.report() = report;
  state_.touched().resize(touched);
  return false;
}
}
