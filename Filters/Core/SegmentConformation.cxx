// SPDX-License-Identifier: GPL-3.0-or-later
#include "SegmentConformation.h"

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
  bool changed = true;
  while (changed)
  {
    changed = false;
    for (size_t s = 0; s < set.subs.size(); ++s)
    {
      const Vec3 a = set.points[set.subs[s][0]], b = set.points[set.subs[s][1]];
      const Vec3 mid = 0.5 * (a + b);
      const double r2 = 0.25 * dot(b - a, b - a);
      bool bad = edgeSize > 0 && 4.0 * r2 > edgeSize * edgeSize;
      if (!bad && s < given.size() && given[s])
        continue;
      for (size_t p = 0; !bad && p < set.points.size(); ++p)
      {
        if (static_cast<int>(p) == set.subs[s][0] || static_cast<int>(p) == set.subs[s][1])
          continue;
        const Vec3 d = set.points[p] - mid;
        bad = dot(d, d) < r2 * (1.0 - 1e-12);
        if (bad && !(2.0 * std::sqrt(r2) >= 2.0 * floor)) // halves would fall below the floor
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
