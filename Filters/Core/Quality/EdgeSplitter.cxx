// SPDX-License-Identifier: GPL-3.0-or-later
#include "EdgeSplitter.h"

#include "HierarchicalOracle.h"

namespace omesh
{
EdgeSplitter::EdgeSplitter(ImprovementMesh& state, const TetFlips& flips, VertexMover& mover)
  : state_(state)
  , flips_(flips)
  , mover_(mover)
  , mesh_(state.mesh())
  , stars_(state.stars())
  , oracle_(state.oracle())
{
}

bool EdgeSplitter::splitEdge(int a, int b)
{
  std::vector<int> ring, old;
  if (!flips_.ringAround(a, b, ring, old))
    return false;
  const double before = state_.worstOf(old);
  const int material = stars_.material(old.front());
  const int m = static_cast<int>(mesh_.points.size());
  state_.addInteriorVertex(splitPoint(a, b, ring, material));
  for (int t : old)
    stars_.remove(t);
  std::vector<int> made;
  for (std::size_t i = 0; i < ring.size(); ++i)
  {
    const int c = ring[i], d = ring[(i + 1) % ring.size()];
    made.push_back(state_.addTet({ a, m, c, d }, material));
    made.push_back(state_.addTet({ m, b, c, d }, material));
  }
  const std::size_t movesBefore = state_.report().interiorMoves;
  mover_.moveVertex(m);
  state_.report().interiorMoves = movesBefore;
  if (state_.starQuality(m) > before + 1e-9 && state_.starAcceptable(m) && oracle_.material(mesh_.points.back()) == material)
  {
    ++state_.report().edgeSplits;
    return true;
  }
  for (int t : made)
    stars_.remove(t);
  for (int t : old)
    stars_.revive(t);
  state_.removeLastVertex();
  return false;
}

Vec3 EdgeSplitter::splitPoint(int a, int b, const std::vector<int>& ring, int material) const
{
  const auto& p = mesh_.points;
  const Vec3 mid = 0.5 * (p[static_cast<std::size_t>(a)] + p[static_cast<std::size_t>(b)]);
  if (oracle_.material(mid) == material)
    return mid;
  Vec3 centre{ 0, 0, 0 };
  for (int v : ring)
    centre = centre + p[static_cast<std::size_t>(v)];
  centre = (1.0 / static_cast<double>(ring.size())) * centre;
  for (double f : { 0.25, 0.5, 0.75 })
  {
    const Vec3 x = mid + f * (centre - mid);
    if (oracle_.material(x) == material)
      return x;
  }
  return mid;
}
}
