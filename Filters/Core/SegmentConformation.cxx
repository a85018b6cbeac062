// SPDX-License-Identifier: GPL-3.0-or-later
#include "SegmentConformation.h"

#include "BoundingBox.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace omesh
{
int SegmentSet::add(const Vec3& p)
{
  points.push_back(p);
  corner.push_back(0);
  return static_cast<int>(points.size()) - 1;
}

int SegmentSet::split(size_t s, double t)
{
  const auto [a, b, input] = subs[s];
  const int m = add(lerp(points[a], points[b], t));
  subs[s] = { a, m, input };
  subs.push_back({ m, b, input });
  return m;
}

SegmentSet conformSegments(const FeatureSegments& f, double edgeSize, size_t maxPoints, std::vector<std::string>& warnings)
{
  SegmentSet set;
  set.points = f.points;
  set.corner.assign(f.points.size(), 1);
  for (size_t s = 0; s < f.segments.size(); ++s)
    set.subs.push_back({ f.segments[s][0], f.segments[s][1], static_cast<int>(s) });
  const std::vector<bool> star = f.starVertices();
  std::vector<double> lmin(f.points.size(), std::numeric_limits<double>::infinity());
  for (size_t s = 0; s < f.segments.size(); ++s)
    for (int end : f.segments[s])
      lmin[end] = std::min(lmin[end], f.length(s));
  // T1.1: every segment at a star vertex p_i gets a point at l_min,i / 3 from p_i.
  for (size_t s = 0, n = set.subs.size(); s < n; ++s)
  {
    for (int side = 0; side < 2; ++side)
    {
      const int a = set.subs[s][0], b = set.subs[s][1];
      const int at = side == 0 ? a : b;
      if (at >= static_cast<int>(star.size()) || !star[at])
        continue;
      const double len = set.length(s), cut = lmin[at] / 3.0;
      if (len <= cut * (1.0 + 1e-9))
        continue;
      // split so that the piece touching `at` has length cut; keep sub-segment s as the piece
      // away from already-trimmed ends
      if (at == a)
      {
        const int m = set.split(s, cut / len); // s = (a, m), new = (m, b)
        std::swap(set.subs[s], set.subs.back()); // s = (m, b) continues, the trimmed piece is done
        (void)m;
      }
      else
        set.split(s, 1.0 - cut / len); // s = (a, m), new = (m, b) is the trimmed piece
      ++set.trims;
    }
  }
  // T1.2: midpoint splits until no sub-segment is encroached by a segment point (or too long).
  // Encroachment splits stop at 1/64 of the shortest piece after T1.1, as in the mesher's
  // refinement: a point almost on another segment (closer than rounding to it) otherwise drew
  // midpoint splits towards it without end (found by fuzzing).
  double shortest = std::numeric_limits<double>::infinity();
  for (size_t s = 0; s < set.subs.size(); ++s)
    shortest = std::min(shortest, set.length(s));
  const double floor = shortest / 64.0;
  std::vector<char> given(set.subs.size(), 0); // encroached but at the floor: left as it is
  size_t unresolved = 0;
  // The points sorted by x, rebuilt every pass (points added during a pass are checked one by
  // one): a sub-segment only looks at the points in the x-slab of its diametral ball, instead of
  // all of them (quadratic: a fine EdgeSize took minutes before the vertex budget was reached).
  std::vector<std::pair<double, int>> byX;
  size_t indexed = 0;
  int axis = 0; // the axis along which the points spread most
  {
    BoundingBox box;
    for (const Vec3& p : set.points)
      box.add(p);
    const Vec3 size = box.size();
    axis = size.x >= size.y && size.x >= size.z ? 0 : (size.y >= size.z ? 1 : 2);
  }
  bool changed = true;
  while (changed)
  {
    changed = false;
    byX.clear();
    for (size_t p = 0; p < set.points.size(); ++p)
      byX.emplace_back(set.points[p][axis], static_cast<int>(p));
    std::sort(byX.begin(), byX.end());
    indexed = set.points.size();
    for (size_t s = 0; s < set.subs.size(); ++s)
    {
      const Vec3 a = set.points[set.subs[s][0]], b = set.points[set.subs[s][1]];
      const Vec3 mid = 0.5 * (a + b);
      const double r2 = 0.25 * dot(b - a, b - a);
      bool bad = edgeSize > 0 && 4.0 * r2 > edgeSize * edgeSize;
      if (!bad && s < given.size() && given[s])
        continue;
      const double r = std::sqrt(r2);
      auto first = std::lower_bound(byX.begin(), byX.end(), std::make_pair(mid[axis] - r, -1));
      auto last = std::upper_bound(byX.begin(), byX.end(), std::make_pair(mid[axis] + r, std::numeric_limits<int>::max()));
      const size_t slab = static_cast<size_t>(last - first);
      for (size_t c = 0; !bad && c < slab + (set.points.size() - indexed); ++c)
      {
        const int p = c < slab ? (first + c)->second : static_cast<int>(indexed + (c - slab));
        if (p == set.subs[s][0] || p == set.subs[s][1])
          continue;
        const Vec3 d = set.points[p] - mid;
        bad = dot(d, d) < r2 * (1.0 - 1e-12);
        if (bad && !(2.0 * r >= 2.0 * floor)) // halves would fall below the floor
        {
          given.resize(set.subs.size(), 0);
          given[s] = 1;
          ++unresolved;
          bad = false;
          break;
        }
      }
      if (bad)
      {
        if (set.points.size() >= maxPoints)
        {
          warnings.push_back("feature lines: segment refinement stopped at " + std::to_string(maxPoints) +
            " points (segments meeting at small angles keep encroaching each other)");
          return set;
        }
        set.split(s, 0.5);
        ++set.splits;
        changed = true;
      }
    }
  }
  if (unresolved)
    warnings.push_back("feature lines: " + std::to_string(unresolved) +
      " sub-segment(s) stay encroached by a point closer to them than 1/64 of the shortest segment piece; "
      "splitting stopped there");
  return set;
}
}
