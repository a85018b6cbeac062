// SPDX-License-Identifier: GPL-3.0-or-later
#include "FeatureSegments.h"

#include "HierarchicalOracle.h"
#include "InputError.h"

#include <CGAL/AABB_segment_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/box_intersection_d.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>

#include "FeatureMerge.h"

namespace omesh
{
double angleAt(const Vec3& v, const Vec3& p, const Vec3& q)
{
  const Vec3 a = p - v, b = q - v;
  const double c = dot(a, b) / (norm(a) * norm(b));
  return std::acos(std::clamp(c, -1.0, 1.0)) * 180.0 / M_PI;
}

namespace
{
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Box = CGAL::Box_intersection_d::Box_with_info_d<double, 3, size_t>;

std::string describeSegment(const FeatureSegments& f, size_t s)
{
  return f.describe(s);
}
}

std::vector<std::vector<size_t>> FeatureSegments::incidence() const
{
  std::vector<std::vector<size_t>> inc(points.size());
  for (size_t s = 0; s < segments.size(); ++s)
  {
    inc[segments[s][0]].push_back(s);
    inc[segments[s][1]].push_back(s);
  }
  return inc;
}

std::vector<bool> FeatureSegments::starVertices() const
{
  const auto inc = incidence();
  std::vector<bool> star(points.size(), false);
  for (size_t p = 0; p < points.size(); ++p)
    star[p] = inc[p].size() >= 2;
  return star;
}

std::vector<std::array<bool, 2>> FeatureSegments::endsBelowRightAngle() const
{
  std::vector<std::array<bool, 2>> below(segments.size(), { false, false });
  const auto inc = incidence();
  for (size_t v = 0; v < inc.size(); ++v)
    for (size_t i = 0; i < inc[v].size(); ++i)
      for (size_t j = i + 1; j < inc[v].size(); ++j)
      {
        const auto& s = segments[inc[v][i]];
        const auto& t = segments[inc[v][j]];
        const int si = s[0] == int(v) ? 0 : 1, tj = t[0] == int(v) ? 0 : 1;
        if (angleAt(points[v], points[s[1 - si]], points[t[1 - tj]]) < 90.0)
          below[inc[v][i]][si] = below[inc[v][j]][tj] = true;
      }
  return below;
}

double FeatureSegments::smallestAngle() const
{
  const auto inc = incidence();
  double smallest = 180.0;
  for (size_t v = 0; v < points.size(); ++v)
  {
    for (size_t i = 0; i < inc[v].size(); ++i)
      for (size_t j = i + 1; j < inc[v].size(); ++j)
      {
        const auto& si = segments[inc[v][i]];
        const auto& sj = segments[inc[v][j]];
        const int pi = si[0] == int(v) ? si[1] : si[0];
        const int pj = sj[0] == int(v) ? sj[1] : sj[0];
        smallest = std::min(smallest, angleAt(points[v], points[pi], points[pj]));
      }
  }
  return smallest;
}

std::vector<std::pair<size_t, size_t>> FeatureSegments::crossingPairs() const
{
  // Segments may meet only at shared end points: any other contact is a crossing.
  const FeatureSegments& f = *this;
  std::vector<Box> boxes;
  boxes.reserve(f.segments.size());
  for (size_t s = 0; s < f.segments.size(); ++s)
  {
    const Vec3& a = f.points[f.segments[s][0]];
    const Vec3& b = f.points[f.segments[s][1]];
    double lo[3] = { std::min(a.x, b.x), std::min(a.y, b.y), std::min(a.z, b.z) };
    double hi[3] = { std::max(a.x, b.x), std::max(a.y, b.y), std::max(a.z, b.z) };
    boxes.emplace_back(lo, hi, s);
  }
  std::vector<std::pair<size_t, size_t>> crossings;
  auto check = [&](const Box& x, const Box& y) {
    const size_t s = x.info(), t = y.info();
    const auto& a = f.segments[s];
    const auto& b = f.segments[t];
    const auto P = [&](int i) { return K::Point_3(f.points[i].x, f.points[i].y, f.points[i].z); };
    const K::Segment_3 ss(P(a[0]), P(a[1])), tt(P(b[0]), P(b[1]));
    int shared = -1;
    for (int i : a)
      for (int j : b)
        if (i == j)
          shared = i;
    if (shared < 0)
    {
      if (CGAL::do_intersect(ss, tt))
        crossings.emplace_back(std::min(s, t), std::max(s, t));
      return;
    }
    // Sharing an end point: they cross only if collinear and overlapping.
    const int pa = a[0] == shared ? a[1] : a[0];
    const int pb = b[0] == shared ? b[1] : b[0];
    if (CGAL::collinear(P(shared), P(pa), P(pb)) &&
      CGAL::angle(P(pa), P(shared), P(pb)) == CGAL::ACUTE)
      crossings.emplace_back(std::min(s, t), std::max(s, t));
  };
  CGAL::box_self_intersection_d(boxes.begin(), boxes.end(), check);
  std::sort(crossings.begin(), crossings.end());
  return crossings;
}

namespace
{
/// Finite, sane coordinates and segments between two distinct points in range; throws InputError.
void checkPointsAndIndices(const FeatureSegments& f)
{
  const int n = static_cast<int>(f.points.size());
  for (int i = 0; i < n; ++i)
  {
    if (!isFinite(f.points[i]))
      throw InputError("feature lines: point " + std::to_string(i) + " has a NaN or infinite coordinate");
    const Vec3& p = f.points[i];
    if (std::max({ std::abs(p.x), std::abs(p.y), std::abs(p.z) }) > 1e15)
    {
      std::ostringstream o;
      o << "feature lines: point " << i << " (" << p.x << ", " << p.y << ", " << p.z
        << ") has a coordinate beyond 1e15 in magnitude (absurd; check the units)";
      throw InputError(o.str());
    }
  }
  for (size_t s = 0; s < f.segments.size(); ++s)
  {
    const auto& seg = f.segments[s];
    if (seg[0] < 0 || seg[0] >= n || seg[1] < 0 || seg[1] >= n)
      throw InputError("feature lines: segment " + std::to_string(s) + " refers to a point out of range");
    if (seg[0] == seg[1] || !(f.length(s) > 0.0))
      throw InputError("feature lines: " + describeSegment(f, s) + " has zero length");
  }
}

/// Segments may meet only at shared end points: any other contact is a crossing; throws InputError.
void checkNoCrossings(const FeatureSegments& f)
{
  const std::vector<std::pair<size_t, size_t>> crossings = f.crossingPairs();
  if (!crossings.empty())
  {
    std::ostringstream msg;
    msg << "feature lines: " << crossings.size() << " pair(s) of segments cross or overlap; first: "
        << describeSegment(f, crossings[0].first) << " and " << describeSegment(f, crossings[0].second);
    throw InputError(msg.str());
  }
}

/// Lines that meet or run along each other only up to rounding (a point within 1e-10 of the
/// lines' diagonal of another point or of a segment, not exactly on it) are neither crossings nor
/// one line to the exact predicates; kept as two, each line's splits encroach the other's
/// sub-segments without end. mergeFeatureSegments makes them one line (the filter calls it).
void checkNoneWithinRounding(const FeatureSegments& f)
{
  FeatureSegments merged = f;
  const FeatureMergeCounts counts = mergeFeatureSegments(merged);
  if (counts.withinRounding)
  {
    const Vec3& p = counts.firstWithinRounding;
    std::ostringstream msg;
    msg << "feature lines: " << counts.withinRounding
        << " point(s) lie within rounding of another point or segment without being on it; first: (" << p.x
        << ", " << p.y << ", " << p.z << ") (merge the lines first: mergeFeatureSegments)";
    throw InputError(msg.str());
  }
}

/// Warnings for segments meeting at less than 60 degrees and for a radius-edge bound below what
/// the smallest angle needs (paper section 5: B < 1/(2 sin alpha0) contradicts the segments). The
/// bound is about small angles only: at 90 degrees and more the segments' diametral balls do not
/// reach each other, and every polyline bends by a few degrees at each vertex (a resampled circle
/// meets itself at 172 degrees, which the formula alone would read as a contradiction of B < 3.7).
void warnSmallAngles(const FeatureSegments& f, double radiusEdgeBound, std::vector<std::string>& warnings)
{
  const auto inc = f.incidence();
  size_t sharp = 0;
  std::string firstSharp;
  double alpha0 = 180.0;
  for (size_t v = 0; v < f.points.size(); ++v)
  {
    for (size_t i = 0; i < inc[v].size(); ++i)
      for (size_t j = i + 1; j < inc[v].size(); ++j)
      {
        const auto& si = f.segments[inc[v][i]];
        const auto& sj = f.segments[inc[v][j]];
        const double angle = angleAt(f.points[v], f.points[si[0] == int(v) ? si[1] : si[0]],
          f.points[sj[0] == int(v) ? sj[1] : sj[0]]);
        alpha0 = std::min(alpha0, angle);
        if (angle < 60.0 && sharp++ == 0)
        {
          std::ostringstream o;
          o << describeSegment(f, inc[v][i]) << " and " << describeSegment(f, inc[v][j]) << " meet at "
            << angle << " degrees";
          firstSharp = o.str();
        }
      }
  }
  if (sharp)
    warnings.push_back("feature lines: " + std::to_string(sharp) +
      " pair(s) of segments meet at less than 60 degrees, where termination is not guaranteed (paper "
      "section 2.2); first: " + firstSharp);
  if (alpha0 < 90.0 && radiusEdgeBound > 0 && radiusEdgeBound < 1.0 / (2.0 * std::sin(alpha0 * M_PI / 180.0)))
  {
    std::ostringstream o;
    o << "criteria contradict the feature lines: radius-edge bound " << radiusEdgeBound << " < 1/(2 sin "
      << alpha0 << " deg) = " << 1.0 / (2.0 * std::sin(alpha0 * M_PI / 180.0))
      << "; refinement may not terminate (it stops at MaximumNumberOfVertices)";
    warnings.push_back(o.str());
  }
}

/// A warning for segments outside every domain.
void warnOutside(const FeatureSegments& f, const HierarchicalOracle& oracle, std::vector<std::string>& warnings)
{
  size_t outside = 0;
  std::string firstOutside;
  for (size_t s = 0; s < f.segments.size(); ++s)
  {
    const Vec3& a = f.points[f.segments[s][0]];
    const Vec3& b = f.points[f.segments[s][1]];
    if (!oracle.touchesMaterial(a, b) && outside++ == 0)
      firstOutside = describeSegment(f, s);
  }
  if (outside)
    warnings.push_back("feature lines: " + std::to_string(outside) +
      " segment(s) lie outside every domain and cannot become mesh edges; first: " + firstOutside);
}
}

std::string FeatureSegments::describe(size_t s) const
{
  const int n = static_cast<int>(points.size());
  if (segments[s][0] < 0 || segments[s][0] >= n || segments[s][1] < 0 || segments[s][1] >= n)
    return "segment " + std::to_string(s);
  const Vec3& a = points[segments[s][0]];
  const Vec3& b = points[segments[s][1]];
  std::ostringstream o;
  o << "segment " << s << " (" << a.x << ", " << a.y << ", " << a.z << ") - (" << b.x << ", " << b.y
    << ", " << b.z << ")";
  return o.str();
}

void FeatureSegments::checkEdgeSizes() const
{
  if (!edgeSizes.empty() && edgeSizes.size() != segments.size())
    throw InputError("feature lines: " + std::to_string(edgeSizes.size()) + " edge sizes for " +
      std::to_string(segments.size()) + " segments (give one per segment, or none)");
  for (size_t s = 0; s < edgeSizes.size(); ++s)
    if (edgeSizes[s] && !(std::isfinite(*edgeSizes[s]) && *edgeSizes[s] >= 0))
    {
      std::ostringstream o;
      o << "feature lines: " << describe(s) << " has EdgeSize " << *edgeSizes[s]
        << " (a number >= 0 is needed: 0 means no bound; leave it unset to take the materials' or the global one)";
      throw InputError(o.str());
    }
}

std::vector<std::string> FeatureSegments::validate(const HierarchicalOracle& oracle, double radiusEdgeBound) const
{
  checkPointsAndIndices(*this);
  checkEdgeSizes();
  checkNoCrossings(*this);
  checkNoneWithinRounding(*this);
  std::vector<std::string> warnings;
  warnSmallAngles(*this, radiusEdgeBound, warnings);
  warnOutside(*this, oracle, warnings);
  return warnings;
}

namespace
{
/// Whether the chord from chain[i] to chain[j] may replace the points between: at most maxLength
/// long (or one segment of the chain) and every point in between within the tolerance of it.
bool chordFits(const std::vector<Vec3>& pts, const std::vector<int>& chain, size_t i, size_t j, double maxLength,
  double tolerance)
{
  const Vec3 &a = pts[chain[i]], &b = pts[chain[j]];
  if (j == i + 1)
    return true;
  if (norm(b - a) > maxLength)
    return false;
  for (size_t k = i + 1; k < j; ++k)
    if (distanceToSegment(pts[chain[k]], a, b) > tolerance)
      return false;
  return true;
}

/// Greedy sleeve: from each kept point, the farthest next point whose chord fits (chordFits; the
/// search stops at the first that does not), at least the next point. The fewest chords, but the
/// last one takes whatever is left. Returns the kept points' positions in `chain`, walked from
/// its end when `backwards`.
std::vector<size_t> greedySleeve(
  const std::vector<Vec3>& pts, std::vector<int> chain, double maxLength, double tolerance, bool backwards)
{
  if (backwards)
    std::reverse(chain.begin(), chain.end());
  std::vector<size_t> kept{ 0 };
  size_t anchor = 0;
  while (anchor + 1 < chain.size())
  {
    size_t best = anchor + 1;
    for (size_t j = anchor + 2; j < chain.size() && chordFits(pts, chain, anchor, j, maxLength, tolerance); ++j)
      best = j;
    kept.push_back(best);
    anchor = best;
  }
  if (backwards)
    for (size_t& k : kept)
      k = chain.size() - 1 - k;
  return kept;
}

/// As many chords as the greedy sleeve, spread evenly: the greedy sleeve leaves its last chord
/// whatever remains, and a found curve ending at a junction then began with a chord of 0.034
/// against 0.75 (a box edge through a ball's surface), whose l_min/3 trims cut every curve there
/// down to 0.011 and the mesh graded down to them. The k-th kept point lies between where the
/// greedy sleeves from the start and from the end get with k and K - k chords (any fewest-chord
/// choice does, where a chord that fits stays fitting when shortened); of those that fit, the one
/// nearest k/K of the arc length is taken. Where that does not work out (a chain whose chords
/// stop fitting when shortened), the greedy sleeve stays.
std::vector<size_t> simplifyChain(const std::vector<Vec3>& pts, const std::vector<int>& chain, double maxLength,
  double tolerance)
{
  const std::vector<size_t> forward = greedySleeve(pts, chain, maxLength, tolerance, false);
  const size_t K = forward.size() - 1;
  if (K < 2)
    return forward;
  const std::vector<size_t> backward = greedySleeve(pts, chain, maxLength, tolerance, true);
  if (backward.size() != forward.size())
    return forward;
  std::vector<double> arc(chain.size(), 0.0);
  for (size_t k = 1; k < chain.size(); ++k)
    arc[k] = arc[k - 1] + norm(pts[chain[k]] - pts[chain[k - 1]]);
  std::vector<size_t> kept{ 0 };
  for (size_t k = 1; k < K; ++k)
  {
    const size_t lo = std::max(backward[K - k], kept.back() + 1), hi = forward[k];
    const double target = arc.back() * static_cast<double>(k) / static_cast<double>(K);
    size_t best = 0;
    for (size_t j = lo; j <= hi; ++j)
      if (chordFits(pts, chain, kept.back(), j, maxLength, tolerance) &&
        (best == 0 || std::abs(arc[j] - target) < std::abs(arc[best] - target)))
        best = j;
    if (best == 0)
      return forward;
    kept.push_back(best);
  }
  if (!chordFits(pts, chain, kept.back(), chain.size() - 1, maxLength, tolerance))
    return forward;
  kept.push_back(chain.size() - 1);
  return kept;
}

/// Points where a chain ends: degree other than 2, or a turn sharper than `cornerAngle`.
std::vector<char> chainCorners(const FeatureSegments& f, const std::vector<std::vector<size_t>>& inc, double cornerAngle)
{
  auto other = [&](size_t seg, int v) { return f.segments[seg][0] == v ? f.segments[seg][1] : f.segments[seg][0]; };
  std::vector<char> corner(f.points.size(), 0);
  for (size_t v = 0; v < f.points.size(); ++v)
  {
    if (inc[v].empty())
      continue;
    if (inc[v].size() != 2)
      corner[v] = 1;
    else
    {
      const int p = other(inc[v][0], static_cast<int>(v)), q = other(inc[v][1], static_cast<int>(v));
      corner[v] = angleAt(f.points[v], f.points[p], f.points[q]) < 180.0 - cornerAngle;
    }
  }
  return corner;
}

/// The segments `out` between f's points, with only the points they use, in order of first use.
FeatureSegments withUsedPoints(const FeatureSegments& f, std::vector<std::array<int, 2>> out)
{
  std::vector<int> index(f.points.size(), -1);
  FeatureSegments r;
  for (auto& s : out)
    for (int& e : s)
    {
      if (index[e] < 0)
      {
        index[e] = static_cast<int>(r.points.size());
        r.points.push_back(f.points[e]);
      }
      e = index[e];
    }
  r.segments = std::move(out);
  return r;
}
}

size_t resampleFeatureLines(FeatureSegments& f, double maxLength, double tolerance, double cornerAngle)
{
  if (f.segments.empty() || !(maxLength > 0) || !(tolerance >= 0))
    return 0;
  const auto inc = f.incidence();
  auto other = [&](size_t seg, int v) { return f.segments[seg][0] == v ? f.segments[seg][1] : f.segments[seg][0]; };
  std::vector<char> corner = chainCorners(f, inc, cornerAngle);
  std::vector<char> used(f.segments.size(), 0);
  std::vector<std::array<int, 2>> out;
  std::vector<int> source;
  // Walks the chain that leaves `start` through segment `first` up to the next corner (or back to start).
  auto walk = [&](int start, size_t first) {
    std::vector<int> chain{ start };
    std::vector<size_t> segs; // segs[i] joins chain[i] and chain[i + 1]
    int v = start;
    size_t seg = first;
    while (true)
    {
      used[seg] = 1;
      segs.push_back(seg);
      v = other(seg, v);
      chain.push_back(v);
      if (corner[v] || v == start)
        break;
      seg = inc[v][0] == seg ? inc[v][1] : inc[v][0];
      if (used[seg])
        break;
    }
    const std::vector<size_t> kept = simplifyChain(f.points, chain, maxLength, tolerance);
    for (size_t k = 0; k + 1 < kept.size(); ++k)
    {
      out.push_back({ chain[kept[k]], chain[kept[k + 1]] });
      if (!f.source.empty())
        source.push_back(f.sourceOfMost(std::vector<size_t>(segs.begin() + kept[k], segs.begin() + kept[k + 1])));
    }
  };
  for (size_t v = 0; v < f.points.size(); ++v)
    if (corner[v])
      for (size_t seg : inc[v])
        if (!used[seg])
          walk(static_cast<int>(v), seg);
  // Loops without a corner: start at their sharpest point, which stays.
  for (size_t seg = 0; seg < f.segments.size(); ++seg)
  {
    if (used[seg])
      continue;
    int start = f.segments[seg][0];
    double sharpest = 180.0;
    for (int v = start, s = static_cast<int>(seg);;)
    {
      const int p = other(inc[v][0], v), q = other(inc[v][1], v);
      const double a = angleAt(f.points[v], f.points[p], f.points[q]);
      if (a < sharpest)
      {
        sharpest = a;
        start = v;
      }
      v = other(s, v);
      s = static_cast<int>(inc[v][0] == static_cast<size_t>(s) ? inc[v][1] : inc[v][0]);
      if (v == f.segments[seg][0])
        break;
    }
    corner[start] = 1;
    walk(start, inc[start][0]);
  }
  // Renumber: only points that end a kept segment remain.
  FeatureSegments r = withUsedPoints(f, std::move(out));
  r.source = std::move(source);
  // two chains between the same corners that both fit one chord become one segment
  mergeFeatureSegments(r);
  const size_t dropped = f.points.size() - r.points.size();
  f = std::move(r);
  return dropped;
}

int FeatureSegments::sourceOfMost(const std::vector<size_t>& segs) const
{
  if (source.empty())
    return -1;
  std::map<int, double> lengthFrom;
  for (size_t s : segs)
    lengthFrom[source[s]] += length(s);
  int best = -1;
  double most = -1.0;
  for (size_t s : segs) // in the order given, so the first wins a tie
    if (lengthFrom[source[s]] > most)
    {
      most = lengthFrom[source[s]];
      best = source[s];
    }
  return best;
}

void transferEdgeSizes(const FeatureSegments& from, FeatureSegments& to, double maxDistance)
{
  to.edgeSizes.clear();
  if (from.edgeSizes.empty() || from.segments.empty())
    return;
  using Segment = K::Segment_3;
  using Iterator = std::vector<Segment>::const_iterator;
  using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, CGAL::AABB_segment_primitive<K, Iterator>>>;
  const auto P = [](const Vec3& p) { return K::Point_3(p.x, p.y, p.z); };
  std::vector<Segment> given;
  given.reserve(from.segments.size());
  for (const auto& s : from.segments)
    given.emplace_back(P(from.points[s[0]]), P(from.points[s[1]]));
  Tree tree(given.begin(), given.end());
  to.edgeSizes.assign(to.segments.size(), std::nullopt);
  for (size_t s = 0; s < to.segments.size(); ++s)
  {
    const K::Point_3 m = P(0.5 * (to.points[to.segments[s][0]] + to.points[to.segments[s][1]]));
    const auto [closest, primitive] = tree.closest_point_and_primitive(m);
    if (std::sqrt(CGAL::squared_distance(m, closest)) <= maxDistance)
      to.edgeSizes[s] = from.edgeSize(static_cast<size_t>(primitive - given.cbegin()));
  }
}
}
