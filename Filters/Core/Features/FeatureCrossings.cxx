// SPDX-License-Identifier: GPL-3.0-or-later
#include "FeatureCrossings.h"

#include <algorithm>
#include <climits>
#include <map>
#include <set>
#include <utility>

namespace omesh::featurelines
{
namespace
{
/// The part [lo, hi] of an edge, reparametrised to [0, 1].
EdgeRegions restrictTo(const EdgeRegions& e, double lo, double hi)
{
  EdgeRegions out;
  size_t k = std::upper_bound(e.t.begin(), e.t.end(), lo) - e.t.begin();
  out.r.push_back(e.r[k]);
  for (; k < e.t.size() && e.t[k] < hi; ++k)
  {
    out.t.push_back((e.t[k] - lo) / (hi - lo));
    out.r.push_back(e.r[k + 1]);
  }
  return out;
}

/// Halves the rectangle across U (acrossU) or V; the new edge comes from the oracle.
std::pair<Rect, Rect> split(const HierarchicalOracle& oracle, const Rect& q, bool acrossU)
{
  Rect a, b;
  if (acrossU)
  {
    const Vec3 hU = 0.5 * q.U;
    const EdgeRegions mid = regionsAlong(oracle, q.o + hU, q.o + hU + q.V);
    a = { q.o, hU, q.V, restrictTo(q.bottom, 0, 0.5), restrictTo(q.top, 0, 0.5), q.left, mid };
    b = { q.o + hU, hU, q.V, restrictTo(q.bottom, 0.5, 1), restrictTo(q.top, 0.5, 1), mid, q.right };
  }
  else
  {
    const Vec3 hV = 0.5 * q.V;
    const EdgeRegions mid = regionsAlong(oracle, q.o + hV, q.o + hV + q.U);
    a = { q.o, q.U, hV, q.bottom, mid, restrictTo(q.left, 0, 0.5), restrictTo(q.right, 0, 0.5) };
    b = { q.o + hV, q.U, hV, mid, q.top, restrictTo(q.left, 0.5, 1), restrictTo(q.right, 0.5, 1) };
  }
  return { a, b };
}
}

EdgeRegions regionsAlong(const HierarchicalOracle& oracle, const Vec3& a, const Vec3& b)
{
  std::vector<double> ts;
  for (const auto& d : oracle.domains())
    d->crossings(a, b, ts);
  std::sort(ts.begin(), ts.end());
  ts.push_back(1.0);
  EdgeRegions e;
  double previous = 0.0;
  for (double t : ts)
  {
    t = std::min(t, 1.0);
    if (!(t > previous))
      continue;
    const Region r = oracle.decide(lerp(a, b, 0.5 * (previous + t)));
    if (e.r.empty())
      e.r.push_back(r);
    else if (r != e.r.back())
    {
      e.t.push_back(previous);
      e.r.push_back(r);
    }
    previous = t;
  }
  if (e.r.empty())
    e.r.push_back(oracle.decide(lerp(a, b, 0.5)));
  return e;
}

std::vector<Region> loopOf(const Rect& q)
{
  std::vector<Region> loop;
  auto push = [&](const Region& r) {
    if (loop.empty() || loop.back() != r)
      loop.push_back(r);
  };
  for (const Region& r : q.bottom.r)
    push(r);
  for (const Region& r : q.right.r)
    push(r);
  for (auto it = q.top.r.rbegin(); it != q.top.r.rend(); ++it)
    push(*it);
  for (auto it = q.left.r.rbegin(); it != q.left.r.rend(); ++it)
    push(*it);
  while (loop.size() > 1 && loop.back() == loop.front())
    loop.pop_back();
  return loop;
}

bool holdsCurve(const std::vector<Region>& loop)
{
  if (loop.size() < 3)
    return false;
  std::map<std::pair<Region, Region>, int> count;
  for (size_t k = 0; k < loop.size(); ++k)
  {
    Region a = loop[k], b = loop[(k + 1) % loop.size()];
    if (b < a)
      std::swap(a, b);
    ++count[{ a, b }];
  }
  for (const auto& [pair, n] : count)
    if (n % 2)
      return true;
  return false;
}

Crossing locate(const HierarchicalOracle& oracle, Rect q, double precision)
{
  for (int step = 0; step < 200 && std::max(norm(q.U), norm(q.V)) > precision; ++step)
  {
    auto [a, b] = split(oracle, q, norm(q.U) >= norm(q.V));
    if (holdsCurve(loopOf(a)))
      q = std::move(a);
    else if (holdsCurve(loopOf(b)))
      q = std::move(b);
    else
      break; // rounding at the last digits: the curve is within this rectangle
  }
  Crossing c;
  c.point = q.o + 0.5 * q.U + 0.5 * q.V;
  c.regions = loopOf(q);
  std::sort(c.regions.begin(), c.regions.end());
  c.regions.erase(std::unique(c.regions.begin(), c.regions.end()), c.regions.end());
  return c;
}

std::vector<int> materialsOf(const Signature& s)
{
  std::vector<int> m;
  for (const Region& r : s)
    m.push_back(r.material);
  std::sort(m.begin(), m.end());
  m.erase(std::unique(m.begin(), m.end()), m.end());
  return m;
}

bool isFeature(const Signature& s)
{
  if (materialsOf(s).size() >= 3)
    return true;
  std::set<int> sheets;
  for (size_t i = 0; i < s.size(); ++i)
    for (size_t j = i + 1; j < s.size(); ++j)
      if (s[i].material != s[j].material)
      {
        const int di = s[i].domain < 0 ? INT_MAX : s[i].domain;
        const int dj = s[j].domain < 0 ? INT_MAX : s[j].domain;
        sheets.insert(std::min(di, dj));
      }
  return sheets.size() >= 2;
}
}
