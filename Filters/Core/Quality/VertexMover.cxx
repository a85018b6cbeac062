// SPDX-License-Identifier: GPL-3.0-or-later
#include "VertexMover.h"

#include "HierarchicalOracle.h"

#include <algorithm>

namespace omesh
{
VertexMover::VertexMover(ImprovementMesh& state)
  : state_(state)
  , mesh_(state.mesh())
  , stars_(state.stars())
  , oracle_(state.oracle())
{
}

double VertexMover::meanEdgeLength(int v) const
{
  double sum = 0.0;
  int count = 0;
  for (int t : stars_.star(v))
    for (int u : stars_.tet(t))
      if (u != v)
      {
        sum += norm(mesh_.points[static_cast<std::size_t>(u)] - mesh_.points[static_cast<std::size_t>(v)]);
        ++count;
      }
  return count ? sum / count : 0.0;
}

Vec3 VertexMover::interfaceNormal(int v) const
{
  Vec3 sum{ 0, 0, 0 };
  const auto pair = state_.sides(v);
  for (int k : state_.interfacesAt(v))
  {
    const auto& tri = mesh_.interfaceTriangles[static_cast<std::size_t>(k)];
    const auto& p = mesh_.points;
    Vec3 n = cross(p[tri[1]] - p[tri[0]], p[tri[2]] - p[tri[0]]);
    // orient by a tetrahedron on the triangle: away from it on the first side, into it on the second
    for (int t : stars_.star(v))
    {
      const auto& q = stars_.tet(t);
      const auto apex = std::find_if(q.begin(), q.end(), [&](int u) { return u != tri[0] && u != tri[1] && u != tri[2]; });
      if (std::count_if(q.begin(), q.end(), [&](int u) { return u == tri[0] || u == tri[1] || u == tri[2]; }) != 3)
        continue;
      const double side = dot(n, p[*apex] - p[tri[0]]);
      if ((stars_.material(t) == pair[0]) == (side > 0))
        n = -1.0 * n;
      break;
    }
    sum = sum + n;
  }
  const double l = norm(sum);
  return l > 0 ? (1.0 / l) * sum : Vec3{ 0, 0, 0 };
}

bool VertexMover::onInterface(int v, const Vec3& normal, double reach, Vec3& x) const
{
  const auto pair = state_.sides(v);
  const Intersection hit = oracle_.intersect(x - reach * normal, x + reach * normal);
  if (!hit.found || hit.materialBefore != pair[0] || hit.materialAfter != pair[1])
    return false;
  x = hit.point;
  return true;
}

bool VertexMover::moveVertex(int v)
{
  const VertexKind kind = state_.kind(v);
  if (kind == VertexKind::Fixed)
    return false;
  Vec3& x = mesh_.points[static_cast<std::size_t>(v)];
  const Vec3 start = x;
  const double length = meanEdgeLength(v);
  const Vec3 normal = kind == VertexKind::Interface ? interfaceNormal(v) : Vec3{ 0, 0, 0 };
  if (kind == VertexKind::Interface && norm(normal) == 0.0)
    return false;
  int worst = -1;
  double current = state_.starQuality(v, &worst);
  std::vector<unsigned> flawsBefore;
  for (int t : stars_.star(v))
    flawsBefore.push_back(state_.flaws(stars_.tet(t), stars_.material(t)));
  Step s{ v, kind, normal, length, stars_.material(stars_.star(v).front()), current, worst, flawsBefore };
  for (int iteration = 0; iteration < 6 && s.current < 1.0; ++iteration)
  {
    // the worst tetrahedron's gradient; where another one blocks it, the axes (a pattern search)
    bool stepped = lineSearch(s, gradient(s.worst, v, 1e-4 * length));
    for (int axis = 0; axis < 6 && !stepped; ++axis)
    {
      Vec3 d{ 0, 0, 0 };
      d[axis / 2] = axis % 2 ? -1.0 : 1.0;
      stepped = lineSearch(s, d);
    }
    if (!stepped)
      break;
  }
  const bool moved = x.x != start.x || x.y != start.y || x.z != start.z;
  if (moved)
    state_.touched().insert(state_.touched().end(), stars_.star(v).begin(), stars_.star(v).end());
  if (moved)
    ++(kind == VertexKind::Interface ? state_.report().surfaceMoves
        : kind == VertexKind::OnLine ? state_.report().lineMoves
                                     : state_.report().interiorMoves);
  return moved;
}

bool VertexMover::lineSearch(Step& s, Vec3 direction)
{
  if (s.kind == VertexKind::Interface)
    direction = direction - dot(direction, s.normal) * s.normal;
  else if (s.kind == VertexKind::OnLine)
  {
    const Vec3& line = state_.lineDirection(s.v);
    direction = dot(direction, line) * line;
  }
  const double dl = norm(direction);
  if (!(dl > 0))
    return false;
  Vec3& x = mesh_.points[static_cast<std::size_t>(s.v)];
  const Vec3 here = x;
  for (double step = 0.2 * s.length; step > 1e-3 * s.length; step *= 0.5)
  {
    Vec3 trial = here + (step / dl) * direction;
    if (s.kind == VertexKind::Interface && !onInterface(s.v, s.normal, 0.5 * s.length, trial))
      continue;
    // an interior vertex stays inside its material (its tetrahedra would reach across otherwise)
    if (s.kind == VertexKind::Interior && oracle_.material(trial) != s.material)
      continue;
    x = trial;
    int w = -1;
    const double q = state_.starQuality(s.v, &w);
    if (q > s.current + 1e-9 && state_.starAcceptable(s.v, &s.flawsBefore))
    {
      s.current = q;
      s.worst = w;
      return true;
    }
    x = here;
  }
  return false;
}

Vec3 VertexMover::gradient(int t, int v, double h)
{
  Vec3& x = mesh_.points[static_cast<std::size_t>(v)];
  const Vec3 at = x;
  Vec3 g{ 0, 0, 0 };
  for (int axis = 0; axis < 3; ++axis)
  {
    x = at;
    x[axis] += h;
    const double up = state_.quality(t);
    x = at;
    x[axis] -= h;
    const double down = state_.quality(t);
    g[axis] = (up - down) / (2 * h);
  }
  x = at;
  return g;
}
}
