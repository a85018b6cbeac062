// SPDX-License-Identifier: GPL-3.0-or-later
#include "FeatureClip.h"

#include "HierarchicalOracle.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>

namespace omesh
{
std::size_t FeatureClipCounts::removed() const
{
  std::size_t n = 0;
  for (const auto& [owner, c] : owners)
    n += c.removed;
  return n;
}

std::size_t FeatureClipCounts::split() const
{
  std::size_t n = 0;
  for (const auto& [owner, c] : owners)
    n += c.split;
  return n;
}

namespace
{
/// Probes around the midpoint m of a piece with direction d: 1e-3 |d| away along each axis (as
/// HierarchicalOracle::touchesMaterial) and on a ring of 64 directions perpendicular to d (a wedge
/// of an input beside its edge as thin as 6 degrees is seen).
template <typename Seen>
bool anyProbe(const Vec3& m, const Vec3& d, Seen seen)
{
  const double length = norm(d);
  const double h = 1e-3 * length;
  for (int axis = 0; axis < 3; ++axis)
    for (double sign : { -1.0, 1.0 })
    {
      Vec3 p = m;
      p[axis] += sign * h;
      if (seen(p))
        return true;
    }
  Vec3 u, v;
  perpendicularPair((1.0 / length) * d, u, v);
  constexpr int kDirections = 64;
  for (int k = 0; k < kDirections; ++k)
  {
    const double phi = 2.0 * M_PI * k / kDirections;
    if (seen(m + (h * std::cos(phi)) * u + (h * std::sin(phi)) * v))
      return true;
  }
  return false;
}

/// Whether the piece pq of a segment owned by `owner` is kept (see clipFeatureSegments).
bool keepPiece(const HierarchicalOracle& oracle, int owner, const Vec3& p, const Vec3& q)
{
  const Vec3 m = lerp(p, q, 0.5);
  const bool userRule = owner < 0 || owner >= static_cast<int>(oracle.domains().size()) ||
    oracle.domains()[static_cast<size_t>(owner)]->isCut();
  if (userRule)
  {
    const auto hasMaterial = [&oracle](const Vec3& x) { return oracle.material(x) != kOutside; };
    return hasMaterial(m) || anyProbe(m, q - p, hasMaterial);
  }
  const auto decidedByOwner = [&oracle, owner](const Vec3& x) { return oracle.decide(x).domain == owner; };
  return decidedByOwner(m) || anyProbe(m, q - p, decidedByOwner);
}

/// The parameters along ab where some domain's material may change (sorted, in (0, 1), those
/// closer than 1e-12 made one), with a change that no domain lists found by bisection.
std::vector<double> cutParameters(const HierarchicalOracle& oracle, const Vec3& a, const Vec3& b)
{
  std::vector<double> ts;
  for (const auto& d : oracle.domains())
    d->crossings(a, b, ts);
  ts.erase(std::remove_if(ts.begin(), ts.end(), [](double t) { return !(t > 1e-12 && t < 1.0 - 1e-12); }), ts.end());
  std::sort(ts.begin(), ts.end());
  std::vector<double> out;
  double previous = 0.0;
  const auto addInterval = [&](double t0, double t1) {
    // inside one interval the labelling is one, up to rounding; a change there (none listed it)
    // is bisected between the interval's quarter points
    const double lo0 = t0 + 0.25 * (t1 - t0), hi0 = t0 + 0.75 * (t1 - t0);
    const Decision dl = oracle.decide(lerp(a, b, lo0)), dh = oracle.decide(lerp(a, b, hi0));
    if (dl != dh)
    {
      double lo = lo0, hi = hi0;
      while (hi - lo > 1e-12)
      {
        const double mid = 0.5 * (lo + hi);
        (oracle.decide(lerp(a, b, mid)) == dl ? lo : hi) = mid;
      }
      out.push_back(hi);
    }
  };
  for (double t : ts)
  {
    if (t - previous <= 1e-12)
      continue;
    addInterval(previous, t);
    out.push_back(t);
    previous = t;
  }
  addInterval(previous, 1.0);
  std::sort(out.begin(), out.end());
  return out;
}

/// a + t (b - a), from the nearer end (so that a piece's new end is as exact as its own end).
Vec3 pointAt(const Vec3& a, const Vec3& b, double t)
{
  return t <= 0.5 ? a + t * (b - a) : b + (1.0 - t) * (a - b);
}

/// The split point at parameter t (a crossing a domain listed, or the bisection's) between the
/// pieces decided `before` and `after` (the decisions at their midpoints), exact to rounding. The
/// boundary belongs to the higher-priority domain of the two sides (domains are closed sets: on a
/// box face the box's, on a cut plane the cut's), so the point sought is the last one of ab that
/// side decides. For each axis along which ab moves, a bisection over the representable values of
/// that coordinate (within 1e-14 of the segment's extent of a + t (b - a), the other coordinates
/// on ab) finds the last value decided as the winner; where moving that coordinate alone by one
/// unit in the last place gives the other side, the boundary there is perpendicular to the axis
/// (a plane x = c, a box face, an axis-aligned surface face) and the point has x exactly c: every
/// line through that boundary point then ends at that same point, not one a unit of rounding
/// beside it. Otherwise (a slanted or curved boundary) the last winner point along the axis of
/// the largest extent, or a + t (b - a) when the bisection does not bracket the change.
Vec3 splitPoint(const HierarchicalOracle& oracle, const Vec3& a, const Vec3& b, double t, const Decision& before,
  const Decision& after)
{
  const Vec3 p = pointAt(a, b, t);
  if (before == after)
    return p;
  const bool beforeWins = before.domain >= 0 && (after.domain < 0 || before.domain < after.domain);
  const Decision& winner = beforeWins ? before : after;
  const Vec3 d = b - a;
  std::array<int, 3> axes{ 0, 1, 2 };
  std::sort(axes.begin(), axes.end(), [&d](int i, int j) { return std::abs(d[i]) > std::abs(d[j]); });
  const auto onAxis = [&](int i, double v) {
    // the point of ab whose coordinate i is v, that coordinate exactly v
    Vec3 q = pointAt(a, b, (v - a[i]) / d[i]);
    q[i] = v;
    return q;
  };
  std::optional<Vec3> fallback;
  for (int i : axes)
  {
    if (d[i] == 0.0)
      continue;
    // w: the winner's side, l: the other, along axis i
    const double e = 1e-14 * (std::abs(a[i]) + std::abs(b[i]));
    const double sign = (beforeWins ? 1.0 : -1.0) * (d[i] > 0 ? 1.0 : -1.0); // from w towards l
    double w = p[i] - sign * e, l = p[i] + sign * e;
    const double lo = std::min(a[i], b[i]), hi = std::max(a[i], b[i]);
    w = std::min(hi, std::max(lo, w));
    l = std::min(hi, std::max(lo, l));
    if (oracle.decide(onAxis(i, w)) != winner || oracle.decide(onAxis(i, l)) == winner)
      continue;
    for (int k = 0; k < 200 && std::nextafter(w, l) != l; ++k)
    {
      const double m = 0.5 * (w + l);
      if (m == w || m == l)
        break;
      (oracle.decide(onAxis(i, m)) == winner ? w : l) = m;
    }
    const Vec3 q = onAxis(i, w);
    Vec3 beside = q;
    beside[i] = std::nextafter(w, l);
    if (oracle.decide(beside) != winner)
      return q; // a boundary perpendicular to axis i: q[i] is its coordinate
    if (!fallback)
      fallback = q;
  }
  return fallback ? *fallback : p;
}

/// The distance below which two points of `f` are one (1e-10 of its bounding box's diagonal), or
/// none when `f` is not fit to clip: a point not finite, a segment's index out of range, edge sizes
/// not one per segment (FeatureSegments::validate and checkEdgeSizes name those).
std::optional<double> clipRounding(const FeatureSegments& f)
{
  const int n = static_cast<int>(f.points.size());
  BoundingBox box;
  for (const Vec3& p : f.points)
  {
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      return std::nullopt; // validate names it
    box.add(p);
  }
  for (const auto& s : f.segments)
    if (s[0] < 0 || s[0] >= n || s[1] < 0 || s[1] >= n)
      return std::nullopt; // validate names it
  const double rounding = 1e-10 * norm(box.size());
  if (!f.edgeSizes.empty() && f.edgeSizes.size() != f.segments.size())
    return std::nullopt; // checkEdgeSizes names it
  return rounding;
}

/// The stretches [t0, t1] of ab between consecutive `cuts` (0 first, 1 last) that keepPiece keeps,
/// consecutive kept pieces joined.
std::vector<std::pair<double, double>> keptStretches(
  const HierarchicalOracle& oracle, int owner, const Vec3& a, const Vec3& b, const std::vector<double>& cuts)
{
  std::vector<std::pair<double, double>> kept;
  for (size_t k = 0; k + 1 < cuts.size(); ++k)
  {
    if (!keepPiece(oracle, owner, pointAt(a, b, cuts[k]), pointAt(a, b, cuts[k + 1])))
      continue;
    if (!kept.empty() && kept.back().second == cuts[k])
      kept.back().second = cuts[k + 1];
    else
      kept.emplace_back(cuts[k], cuts[k + 1]);
  }
  return kept;
}

/// `f` without the points no segment uses, the others in their order.
FeatureSegments withoutUnusedPoints(FeatureSegments f)
{
  std::vector<int> index(f.points.size(), -1);
  for (const auto& seg : f.segments)
    index[seg[0]] = index[seg[1]] = 0;
  FeatureSegments result;
  for (size_t i = 0; i < f.points.size(); ++i)
    if (index[i] == 0)
    {
      index[i] = static_cast<int>(result.points.size());
      result.points.push_back(f.points[i]);
    }
  for (const auto& seg : f.segments)
    result.segments.push_back({ index[seg[0]], index[seg[1]] });
  result.edgeSizes = std::move(f.edgeSizes);
  result.source = std::move(f.source);
  return result;
}
}

FeatureClipCounts clipFeatureSegments(FeatureSegments& f, const HierarchicalOracle& oracle, const std::vector<int>& owners)
{
  FeatureClipCounts counts;
  if (f.segments.empty() || oracle.empty())
    return counts;
  if (!owners.empty() && owners.size() != f.segments.size())
    throw std::logic_error("clipFeatureSegments: " + std::to_string(owners.size()) + " owners for " +
      std::to_string(f.segments.size()) + " segments");
  const std::optional<double> fit = clipRounding(f);
  if (!fit)
    return counts; // validate or checkEdgeSizes names the problem
  const double rounding = *fit;
  const bool sized = !f.edgeSizes.empty(), sourced = !f.source.empty();

  FeatureSegments out;
  out.points = f.points;
  const auto add = [&](int i, int j, size_t s) {
    out.segments.push_back({ i, j });
    if (sized)
      out.edgeSizes.push_back(f.edgeSizes[s]);
    if (sourced)
      out.source.push_back(f.source[s]);
  };
  for (size_t s = 0; s < f.segments.size(); ++s)
  {
    const int owner = owners.empty() ? kUserLine : owners[s];
    const Vec3 a = f.points[f.segments[s][0]], b = f.points[f.segments[s][1]];
    if (norm(b - a) == 0.0)
    {
      add(f.segments[s][0], f.segments[s][1], s); // validate names it
      continue;
    }
    std::vector<double> cuts = cutParameters(oracle, a, b);
    cuts.insert(cuts.begin(), 0.0);
    cuts.push_back(1.0);
    std::vector<Decision> decisions; // at each interval's midpoint
    for (size_t k = 0; k + 1 < cuts.size(); ++k)
      decisions.push_back(oracle.decide(pointAt(a, b, 0.5 * (cuts[k] + cuts[k + 1]))));
    const auto decisionAround = [&](double t, bool beforeT) {
      const size_t k = static_cast<size_t>(std::lower_bound(cuts.begin(), cuts.end(), t) - cuts.begin());
      return decisions[beforeT ? k - 1 : k]; // cuts[k] == t, 0 < t < 1
    };
    const std::vector<std::pair<double, double>> kept = keptStretches(oracle, owner, a, b, cuts);
    if (kept.size() == 1 && kept[0].first == 0.0 && kept[0].second == 1.0)
    {
      add(f.segments[s][0], f.segments[s][1], s);
      continue;
    }
    auto& c = counts.owners[owner];
    std::size_t pieces = 0;
    for (const auto& [t0, t1] : kept)
    {
      const Vec3 p = t0 == 0.0 ? a : splitPoint(oracle, a, b, t0, decisionAround(t0, true), decisionAround(t0, false));
      const Vec3 q = t1 == 1.0 ? b : splitPoint(oracle, a, b, t1, decisionAround(t1, true), decisionAround(t1, false));
      if (norm(q - p) <= rounding)
        continue;
      const auto vertex = [&](double t, const Vec3& x) {
        if (t == 0.0)
          return f.segments[s][0];
        if (t == 1.0)
          return f.segments[s][1];
        out.points.push_back(x);
        return static_cast<int>(out.points.size()) - 1;
      };
      const int i = vertex(t0, p);
      add(i, vertex(t1, q), s);
      ++pieces;
    }
    ++(pieces ? c.split : c.removed);
  }
  if (!counts.changed())
    return counts;
  f = withoutUnusedPoints(std::move(out));
  return counts;
}
}
