// SPDX-License-Identifier: GPL-3.0-or-later
#include "HierarchicalOracle.h"

#include "InputError.h"

#include <algorithm>
#include <set>

namespace omesh
{
void HierarchicalOracle::add(std::shared_ptr<const Domain> domain)
{
  if (!domain)
    throw InputError("HierarchicalOracle: null domain");
  domains_.push_back(std::move(domain));
}

Intersection HierarchicalOracle::intersect(const Vec3& a, const Vec3& b) const
{
  Intersection result;
  thread_local std::vector<double> ts; // reused: the mesher asks millions of times
  ts.clear();
  if (domains_.size() == 1) // its first change is the oracle's
  {
    const Domain& d = *domains_[0];
    bool shown = false;
    ShownChange change;
    if (d.isCut())
      shown = d.firstCrossings(a, b, ts, 1);
    else if (d.firstChange(a, b, change, ts, shown))
    {
      // the domain showed the material at a and its first change: what the checks below give
      result.materialBefore = change.before;
      if (change.found)
      {
        result.found = true;
        result.t = change.t;
        result.point = lerp(a, b, change.t);
        result.materialAfter = change.after;
      }
      return result;
    }
    result.materialBefore = material(a);
    // shown to keep one material along ab: the checks below would find no change
    if (shown)
      return result;
  }
  else
  {
    result.materialBefore = material(a);
    for (const auto& d : domains_)
      d->crossings(a, b, ts);
  }
  std::sort(ts.begin(), ts.end());
  ts.push_back(1.0);
  double previous = 0.0;
  for (double t : ts)
  {
    if (t <= previous)
      continue;
    const int m = material(lerp(a, b, 0.5 * (previous + t)));
    if (m != result.materialBefore)
    {
      result.found = true;
      result.t = previous;
      result.point = lerp(a, b, previous);
      result.materialAfter = m;
      return result;
    }
    previous = t;
  }
  const int mb = material(b);
  if (mb == result.materialBefore)
    return result;
  // Fallback: bisection between the last interval that agrees with a, and b.
  double lo = 0.0, hi = 1.0;
  while (hi - lo > 1e-12)
  {
    const double mid = 0.5 * (lo + hi);
    (material(lerp(a, b, mid)) == result.materialBefore ? lo : hi) = mid;
  }
  result.found = true;
  result.t = hi;
  result.point = lerp(a, b, hi);
  result.materialAfter = mb;
  return result;
}

bool HierarchicalOracle::touchesMaterial(const Vec3& a, const Vec3& b) const
{
  const Vec3 m = lerp(a, b, 0.5);
  if (material(a) != kOutside || material(b) != kOutside || material(m) != kOutside || intersect(a, b).found)
    return true;
  const double h = 1e-3 * norm(b - a);
  for (int axis = 0; axis < 3; ++axis)
    for (double sign : { -1.0, 1.0 })
    {
      Vec3 p = m;
      p[axis] += sign * h;
      if (material(p) != kOutside)
        return true;
    }
  return false;
}

BoundingBox HierarchicalOracle::bounds() const
{
  if (domains_.empty())
    throw InputError("HierarchicalOracle: no domains");
  BoundingBox box;
  for (const auto& d : domains_)
  {
    if (d->isCut())
      continue;
    if (!d->bounded())
      throw InputError("HierarchicalOracle: domain '" + d->name() + "' (" + d->kind() +
        ") is unbounded; only cut domains may be unbounded (make it a cut: scene \"cut\": true, SetCut(true), Cut in ParaView; Cut is off by default)");
    box.add(d->bounds());
  }
  if (box.empty())
    throw InputError("HierarchicalOracle: every domain is a cut, so no material is left");
  return box;
}

std::vector<int> HierarchicalOracle::materials() const
{
  std::set<int> all;
  for (const auto& d : domains_)
  {
    if (!d->isCut())
    {
      for (int m : d->materials())
        all.insert(m);
    }
  }
  return { all.begin(), all.end() };
}
}
