// SPDX-License-Identifier: GPL-3.0-or-later
#include "TetFlips.h"

#include <algorithm>
#include <limits>
#include <unordered_set>

namespace omesh
{
TetFlips::TetFlips(ImprovementMesh& state)
  : state_(state)
  , stars_(state.stars())
{
}

bool TetFlips::ringAround(int a, int b, std::vector<int>& ring, std::vector<int>& tets) const
{
  if (state_.isKept(a, b))
    return false;
  tets = stars_.around(a, b);
  if (tets.size() < 3 || tets.size() > 7)
    return false;
  const int material = stars_.material(tets.front());
  std::vector<std::pair<int, int>> next; // (c, d) with (a, b, c, d) positive
  for (int t : tets)
  {
    if (stars_.material(t) != material)
      return false;
    int cd[2], k = 0;
    for (int v : stars_.tet(t))
      if (v != a && v != b)
        cd[k++] = v;
    if (state_.isInterface(a, b, cd[0]) || state_.isInterface(a, b, cd[1]))
      return false;
    if (state_.orient({ a, b, cd[0], cd[1] }) < 0)
      std::swap(cd[0], cd[1]);
    next.emplace_back(cd[0], cd[1]);
  }
  ring.assign(1, next.front().first);
  for (std::size_t k = 1; k < next.size(); ++k)
  {
    const auto it = std::find_if(next.begin(), next.end(), [&](const auto& e) { return e.first == ring.back(); });
    if (it == next.end())
      return false;
    ring.push_back(it->second);
  }
  const auto last = std::find_if(next.begin(), next.end(), [&](const auto& e) { return e.first == ring.back(); });
  return last != next.end() && last->second == ring.front() &&
    std::unordered_set<int>(ring.begin(), ring.end()).size() == ring.size();
}

bool TetFlips::removeEdge(int a, int b, std::vector<int>* made, std::vector<int>* removed)
{
  std::vector<int> ring, old;
  if (!ringAround(a, b, ring, old))
    return false;
  const double before = made ? 0.0 : state_.worstOf(old);
  const int n = static_cast<int>(ring.size());
  auto pairQuality = [&](int i, int k, int j) {
    return std::min(state_.quality({ ring[i], ring[k], ring[j], b }), state_.quality({ ring[j], ring[k], ring[i], a }));
  };
  std::vector<double> best(n * n, std::numeric_limits<double>::infinity());
  std::vector<int> split(n * n, -1);
  for (int len = 2; len < n; ++len)
    for (int i = 0; i + len < n; ++i)
    {
      const int j = i + len;
      double top = -std::numeric_limits<double>::infinity();
      for (int k = i + 1; k < j; ++k)
      {
        const double q = std::min({ best[i * n + k], best[k * n + j], pairQuality(i, k, j) });
        if (q > top)
        {
          top = q;
          split[i * n + j] = k;
        }
      }
      best[i * n + j] = top;
    }
  if (!(best[n - 1] > before + 1e-9))
    return false;
  const int material = stars_.material(old.front());
  std::vector<std::array<int, 4>> tets;
  std::vector<std::pair<int, int>> todo{ { 0, n - 1 } };
  while (!todo.empty())
  {
    const auto [i, j] = todo.back();
    todo.pop_back();
    if (j - i < 2)
      continue;
    const int k = split[i * n + j];
    tets.push_back({ ring[i], ring[k], ring[j], b });
    tets.push_back({ ring[j], ring[k], ring[i], a });
    todo.push_back({ i, k });
    todo.push_back({ k, j });
  }
  for (const auto& m : tets)
    if (!state_.acceptable(m, material))
      return false;
  for (int t : old)
    stars_.remove(t);
  for (const auto& m : tets)
  {
    const int id = state_.addTet(m, material);
    if (made)
      made->push_back(id);
  }
  if (removed)
    *removed = old;
  ++state_.report().edgeRemovals;
  return true;
}

bool TetFlips::removeFace(int t, int f)
{
  const auto q = stars_.tet(t);
  const int d = q[f];
  const int a = q[(f + 1) & 3], b = q[(f + 2) & 3], c = q[(f + 3) & 3];
  if (state_.isInterface(a, b, c))
    return false;
  const int other = stars_.beyond(t, a, b, c);
  if (other < 0 || stars_.material(other) != stars_.material(t))
    return false;
  int e = -1;
  for (int v : stars_.tet(other))
    if (v != a && v != b && v != c)
      e = v;
  std::array<int, 3> ring{ a, b, c };
  if (state_.orient({ d, e, a, b }) < 0)
    std::swap(ring[1], ring[2]);
  const std::array<std::array<int, 4>, 3> made{ { { d, e, ring[0], ring[1] }, { d, e, ring[1], ring[2] },
    { d, e, ring[2], ring[0] } } };
  const double before = std::min(state_.quality(t), state_.quality(other));
  double after = std::numeric_limits<double>::infinity();
  for (const auto& m : made)
    after = std::min(after, state_.quality(m));
  const int material = stars_.material(t);
  if (!(after > before + 1e-9) ||
    !std::all_of(made.begin(), made.end(), [&](const auto& m) { return state_.acceptable(m, material); }))
    return false;
  stars_.remove(t);
  stars_.remove(other);
  for (const auto& m : made)
    state_.addTet(m, material);
  ++state_.report().faceRemovals;
  return true;
}
}
