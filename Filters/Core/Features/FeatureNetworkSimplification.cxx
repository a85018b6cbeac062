// SPDX-License-Identifier: GPL-3.0-or-later
#include "FeatureNetworkSimplification.h"

#include "FeatureMerge.h"
#include "UnionFind.h"

#include <CGAL/AABB_segment_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Fuzzy_sphere.h>
#include <CGAL/Kd_tree.h>
#include <CGAL/Search_traits_3.h>
#include <CGAL/Search_traits_adapter.h>
#include <CGAL/property_map.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <array>
#include <set>
#include <numeric>
#include <tuple>

namespace omesh
{
namespace
{
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = K::Point_3;
using Segment = K::Segment_3;
using SegmentIterator = std::vector<Segment>::const_iterator;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, CGAL::AABB_segment_primitive<K, SegmentIterator>>>;
using PointMap = CGAL::Pointer_property_map<Point>::const_type;
using KdTraits = CGAL::Search_traits_adapter<std::size_t, PointMap, CGAL::Search_traits_3<K>>;
using KdTree = CGAL::Kd_tree<KdTraits>;
using Sphere = CGAL::Fuzzy_sphere<KdTraits>;

Point toPoint(const Vec3& v) { return { v.x, v.y, v.z }; }

std::vector<Segment> cgalSegments(const FeatureSegments& f)
{
  std::vector<Segment> s;
  s.reserve(f.segments.size());
  for (const auto& seg : f.segments)
    s.emplace_back(toPoint(f.points[seg[0]]), toPoint(f.points[seg[1]]));
  return s;
}

/// Whether a segment stays within FeatureNetworkTolerances::maxDeviation of the given lines:
/// samples at most a quarter of it apart, each within it (so the segment within 1.125 times it).
/// The bound holds on the clean lines only (appliesTo): the connected pieces of the given network
/// in which no two segments at a point meet at less than `minAngle` (CAD edges: circles, polygons,
/// a box's corners at 90 degrees). A noisy network (the sharp edges of a scanned surface: segments
/// at small angles everywhere) is simplified at the merge distance as before: its shape is noise,
/// and kept to the chord tolerance its detail made refinement run for minutes (noisy_features.py
/// medium: 2.8 s before, over 300 s bounded).
class DeviationBound
{
public:
  DeviationBound(const FeatureSegments& given, double bound, double minAngle)
    : bound_(bound)
    , segments_(cgalSegments(given))
  {
    if (!bounded())
      return;
    tree_.insert(segments_.begin(), segments_.end());
    tree_.accelerate_distance_queries();
    // the clean connected pieces
    UnionFind pieces(given.points.size());
    for (const auto& seg : given.segments)
      pieces.join(static_cast<std::size_t>(seg[0]), static_cast<std::size_t>(seg[1]));
    std::vector<char> noisy(given.points.size(), 0);
    const auto inc = given.incidence();
    for (std::size_t v = 0; v < given.points.size(); ++v)
      for (std::size_t i = 0; i < inc[v].size(); ++i)
        for (std::size_t j = i + 1; j < inc[v].size(); ++j)
        {
          const auto other = [&](std::size_t s) {
            return given.points[given.segments[s][0] == static_cast<int>(v) ? given.segments[s][1] : given.segments[s][0]];
          };
          if (angleAt(given.points[v], other(inc[v][i]), other(inc[v][j])) < minAngle)
            noisy[pieces.find(v)] = 1;
        }
    for (std::size_t v = 0; v < given.points.size(); ++v)
      if (!inc[v].empty() && !noisy[pieces.find(v)])
        clean_.insert(key(given.points[v]));
  }
  bool bounded() const { return std::isfinite(bound_) && !segments_.empty(); }
  /// Whether the bound holds at input point p (on a clean line).
  bool appliesTo(const Vec3& p) const { return bounded() && clean_.count(key(p)) > 0; }
  bool allows(const Vec3& a, const Vec3& b) const
  {
    if (!bounded())
      return true;
    const int n = std::max(1, static_cast<int>(std::ceil(norm(b - a) / (0.25 * bound_))));
    if (n > 100000)
      return false;
    for (int k = 0; k <= n; ++k)
      if (tree_.squared_distance(toPoint(lerp(a, b, static_cast<double>(k) / n))) > bound_ * bound_)
        return false;
    return true;
  }

private:
  static std::array<double, 3> key(const Vec3& p) { return { p.x, p.y, p.z }; }
  double bound_;
  std::vector<Segment> segments_;
  Tree tree_;
  std::set<std::array<double, 3>> clean_; ///< the points of the clean pieces (kept points are input points)
};

std::vector<std::size_t> degrees(const FeatureSegments& f)
{
  std::vector<std::size_t> d(f.points.size(), 0);
  for (const auto& s : f.segments)
  {
    ++d[s[0]];
    ++d[s[1]];
  }
  return d;
}

/// Only the points some segment uses, renumbered.
void keepUsedPoints(FeatureSegments& f)
{
  std::vector<int> index(f.points.size(), -1);
  std::vector<Vec3> points;
  for (auto& s : f.segments)
    for (int& e : s)
    {
      if (index[e] < 0)
      {
        index[e] = static_cast<int>(points.size());
        points.push_back(f.points[e]);
      }
      e = index[e];
    }
  f.points = std::move(points);
}

/// Keeps the segments (and their sources) where `keep`.
void keepSegments(FeatureSegments& f, const std::vector<char>& keep)
{
  std::size_t n = 0;
  for (std::size_t s = 0; s < f.segments.size(); ++s)
    if (keep[s])
    {
      f.segments[n] = f.segments[s];
      if (!f.source.empty())
        f.source[n] = f.source[s];
      ++n;
    }
  f.segments.resize(n);
  if (!f.source.empty())
    f.source.resize(n);
}

/// A segment that a merge or a snap made a copy of one that stayed in place is that one: it takes
/// its source, so the copy mergeFeatureSegments keeps (the first) comes from the line that is there.
void copiesTakeSourceOfUnmoved(FeatureSegments& f, const std::vector<char>& moved)
{
  if (f.source.empty())
    return;
  std::map<std::pair<int, int>, int> unmoved;
  const auto key = [](const std::array<int, 2>& s) { return std::make_pair(std::min(s[0], s[1]), std::max(s[0], s[1])); };
  for (std::size_t s = 0; s < f.segments.size(); ++s)
    if (!moved[s])
      unmoved.emplace(key(f.segments[s]), f.source[s]);
  for (std::size_t s = 0; s < f.segments.size(); ++s)
    if (moved[s])
      if (const auto it = unmoved.find(key(f.segments[s])); it != unmoved.end())
        f.source[s] = it->second;
}

/// Segments renumbered by `to`, without the ones that became a point, then repeated points and
/// segments merged and unused points removed (mergeFeatureSegments).
void remapSegments(FeatureSegments& f, const std::vector<int>& to)
{
  std::vector<char> keep(f.segments.size()), moved(f.segments.size());
  for (std::size_t i = 0; i < f.segments.size(); ++i)
  {
    auto& s = f.segments[i];
    moved[i] = to[s[0]] != s[0] || to[s[1]] != s[1];
    s = { to[s[0]], to[s[1]] };
    keep[i] = s[0] != s[1];
  }
  copiesTakeSourceOfUnmoved(f, moved);
  keepSegments(f, keep);
  mergeFeatureSegments(f);
}

/// Step 1: greedy clustering, highest degree first: each point not yet taken keeps its place and
/// takes every untaken point within `d` (a kd-tree range query). Returns the points merged.
std::size_t mergeNearbyPoints(FeatureSegments& f, double d, const DeviationBound& bound)
{
  const std::size_t n = f.points.size();
  std::vector<Point> pts(n);
  for (std::size_t i = 0; i < n; ++i)
    pts[i] = toPoint(f.points[i]);
  std::vector<std::size_t> ids(n);
  std::iota(ids.begin(), ids.end(), 0);
  KdTree tree(ids.begin(), ids.end(), KdTree::Splitter(), KdTraits(PointMap(pts.data())));
  const auto deg = degrees(f);
  std::vector<std::size_t> order = ids;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return deg[a] > deg[b]; });
  std::vector<int> to(n, -1);
  std::size_t merged = 0;
  std::vector<std::size_t> near;
  // with a deviation bound: w goes to v only where its segments, from v to where their other ends
  // are by now (merged or not yet), stay near the given lines (a later merge of an end checks again)
  std::vector<std::vector<int>> adjacent;
  if (bound.bounded())
  {
    adjacent.resize(n);
    for (const auto& s : f.segments)
    {
      adjacent[s[0]].push_back(s[1]);
      adjacent[s[1]].push_back(s[0]);
    }
  }
  const auto mergeStaysNear = [&](std::size_t w, std::size_t v) {
    if (!bound.appliesTo(f.points[w]) && !bound.appliesTo(f.points[v]))
      return true;
    for (int r : adjacent[w])
    {
      const int at = to[r] >= 0 ? to[r] : r;
      if (at != static_cast<int>(v) && !bound.allows(f.points[v], f.points[at]))
        return false;
    }
    return true;
  };
  for (std::size_t v : order)
  {
    if (to[v] >= 0)
      continue;
    to[v] = static_cast<int>(v);
    near.clear();
    tree.search(std::back_inserter(near), Sphere(pts[v], d, 0.0, KdTraits(PointMap(pts.data()))));
    for (std::size_t w : near)
      if (to[w] < 0 && CGAL::squared_distance(pts[v], pts[w]) < d * d && mergeStaysNear(w, v))
      {
        to[w] = static_cast<int>(v);
        ++merged;
      }
  }
  if (merged)
    remapSegments(f, to);
  return merged;
}

/// For each point, its neighbours along the segments, sorted.
std::vector<std::vector<int>> neighbours(const FeatureSegments& f)
{
  std::vector<std::vector<int>> n(f.points.size());
  for (const auto& s : f.segments)
  {
    n[s[0]].push_back(s[1]);
    n[s[1]].push_back(s[0]);
  }
  for (auto& v : n)
    std::sort(v.begin(), v.end());
  return n;
}

/// Snapping p (closer than d to segment ab) into ab helps where p is no neighbour of a or b (a
/// near-touch becomes a junction), or where it is one at an angle below 45 degrees (the pair then
/// shares a trunk; the total length of the lines drops, so such snaps cannot cycle). Three
/// neighbours at wider angles (a small fat triangle) are left as they are.
bool worthSnapping(const FeatureSegments& f, const std::vector<std::vector<int>>& adjacent, int p, int a, int b)
{
  const auto& n = adjacent[p];
  const bool nextToA = std::binary_search(n.begin(), n.end(), a);
  const bool nextToB = std::binary_search(n.begin(), n.end(), b);
  if (!nextToA && !nextToB)
    return true;
  constexpr double trunkAngle = 45.0;
  return (nextToA && angleAt(f.points[a], f.points[p], f.points[b]) < trunkAngle) ||
    (nextToB && angleAt(f.points[b], f.points[p], f.points[a]) < trunkAngle);
}

/// The segments at each point.
std::vector<std::vector<std::size_t>> incidentSegments(const FeatureSegments& f)
{
  std::vector<std::vector<std::size_t>> inc(f.points.size());
  for (std::size_t i = 0; i < f.segments.size(); ++i)
  {
    inc[f.segments[i][0]].push_back(i);
    inc[f.segments[i][1]].push_back(i);
  }
  return inc;
}

/// A point to put into a segment (step 2), `distance` from it.
struct SnapCandidate
{
  double distance;
  std::size_t segment;
  int point;
  bool trunk = false; ///< two segments at a small angle (smallAngleCandidates), not a near-touch
  bool operator<(const SnapCandidate& o) const
  {
    return std::tie(distance, segment, point) < std::tie(o.distance, o.segment, o.point);
  }
};

/// Points closer than d to a segment they do not end, where worthSnapping.
void nearSegmentCandidates(const FeatureSegments& f, double d, std::vector<SnapCandidate>& candidates)
{
  const std::vector<Segment> segs = cgalSegments(f);
  Tree tree(segs.begin(), segs.end());
  std::vector<Tree::Primitive_id> hits;
  const auto deg = degrees(f);
  const auto adjacent = neighbours(f);
  for (std::size_t p = 0; p < f.points.size(); ++p)
  {
    if (deg[p] == 0)
      continue;
    const Point q = toPoint(f.points[p]);
    hits.clear();
    tree.all_intersected_primitives(
      CGAL::Bbox_3(q.x() - d, q.y() - d, q.z() - d, q.x() + d, q.y() + d, q.z() + d), std::back_inserter(hits));
    for (const auto& it : hits)
    {
      const std::size_t s = static_cast<std::size_t>(it - segs.begin());
      const auto& e = f.segments[s];
      const int pi = static_cast<int>(p);
      if (e[0] == pi || e[1] == pi)
        continue;
      const double dist2 = CGAL::squared_distance(q, *it);
      if (dist2 < d * d && worthSnapping(f, adjacent, pi, e[0], e[1]))
        candidates.push_back({ std::sqrt(dist2), s, pi });
    }
  }
}

/// Small angles at shared points, at any distance: the shorter segment's far end goes into the longer.
void smallAngleCandidates(const FeatureSegments& f, double minAngle, std::vector<SnapCandidate>& candidates)
{
  const auto inc = incidentSegments(f);
  for (std::size_t v = 0; v < f.points.size(); ++v)
    for (std::size_t i = 0; i < inc[v].size(); ++i)
      for (std::size_t j = i + 1; j < inc[v].size(); ++j)
      {
        std::size_t shorter = inc[v][i], longer = inc[v][j];
        if (f.length(longer) < f.length(shorter))
          std::swap(shorter, longer);
        const int vi = static_cast<int>(v);
        const int p = f.segments[shorter][0] == vi ? f.segments[shorter][1] : f.segments[shorter][0];
        const int q = f.segments[longer][0] == vi ? f.segments[longer][1] : f.segments[longer][0];
        const double angle = angleAt(f.points[v], f.points[p], f.points[q]);
        if (angle < minAngle)
          candidates.push_back({ f.length(shorter) * std::sin(angle * M_PI / 180.0), longer, p, true });
      }
}

/// Step 2, one round: the closest (point, segment) pairs first, each split only where none of its
/// three points took part in a split of this round (so the splits are independent, as if made one
/// after the other, and two segments cannot split each other back and forth). Returns the splits.
std::size_t snapPointsToSegments(FeatureSegments& f, double d, double minAngle, const DeviationBound& bound)
{
  if (f.segments.empty())
    return 0;
  std::vector<SnapCandidate> candidates;
  nearSegmentCandidates(f, d, candidates);
  if (minAngle > 0)
    smallAngleCandidates(f, minAngle, candidates);
  std::sort(candidates.begin(), candidates.end());
  std::vector<char> taken(f.points.size(), 0);
  std::vector<int> splitAt(f.segments.size(), -1);
  std::size_t count = 0;
  for (const SnapCandidate& c : candidates)
  {
    const auto& e = f.segments[c.segment];
    if (taken[e[0]] || taken[e[1]] || taken[c.point])
      continue;
    if (!c.trunk && (bound.appliesTo(f.points[c.point]) || bound.appliesTo(f.points[e[0]]) || bound.appliesTo(f.points[e[1]])) &&
      (!bound.allows(f.points[e[0]], f.points[c.point]) || !bound.allows(f.points[c.point], f.points[e[1]])))
      continue; // would move the line too far from the given one
    taken[e[0]] = taken[e[1]] = taken[c.point] = 1;
    splitAt[c.segment] = c.point;
    ++count;
  }
  if (!count)
    return 0;
  FeatureSegments out;
  out.points = std::move(f.points);
  out.segments.reserve(f.segments.size() + count);
  std::vector<char> split; // the halves: a shared trunk's is a copy of the shorter segment, which stays
  for (std::size_t s = 0; s < f.segments.size(); ++s)
  {
    const int from = f.source.empty() ? -1 : f.source[s];
    const auto add = [&](const std::array<int, 2>& e, bool half) {
      out.segments.push_back(e);
      split.push_back(half);
      if (from >= 0)
        out.source.push_back(from);
    };
    if (splitAt[s] < 0)
      add(f.segments[s], false);
    else
    {
      add({ f.segments[s][0], splitAt[s] }, true);
      add({ splitAt[s], f.segments[s][1] }, true);
    }
  }
  copiesTakeSourceOfUnmoved(out, split);
  f = std::move(out);
  mergeFeatureSegments(f);
  return count;
}

/// Step 2 until nothing moves (at most `rounds`, a backstop): a split can bring a new segment near a point.
std::size_t snapUntilStable(FeatureSegments& f, double d, double minAngle, const DeviationBound& bound, int rounds = 64)
{
  std::size_t total = 0;
  for (int r = 0; r < rounds; ++r)
  {
    const std::size_t n = snapPointsToSegments(f, d, minAngle, bound);
    total += n;
    if (!n)
      break;
  }
  return total;
}

/// A run of segments from a point to the next point of degree other than 2.
struct Chain
{
  std::vector<std::size_t> segs;
  double length = 0.0;
  int end = -1; ///< the point of degree other than 2 it reaches (-1: a loop)
};

/// Step 3's view of the network: the chains, and which segments are dropped.
class SpurRemoval
{
public:
  explicit SpurRemoval(const FeatureSegments& f)
    : f_(f)
    , deg_(degrees(f))
    , inc_(incidentSegments(f))
    , drop_(f.segments.size(), 0)
    , seen_(f.segments.size(), 0)
  {
  }

  /// Spurs shorter than s, grouped by their branch point: a branch point whose chains are all
  /// spurs keeps its longest; separate short chains go too.
  void dropSpurs(double s, FeatureNetworkReport& report)
  {
    std::vector<std::vector<Chain>> spursAt(f_.points.size());
    for (std::size_t v = 0; v < f_.points.size(); ++v)
    {
      if (deg_[v] != 1 || seen_[inc_[v][0]])
        continue;
      Chain c = walk(static_cast<int>(v), inc_[v][0]);
      if (c.length >= s)
        continue;
      if (deg_[c.end] == 1) // a separate short chain
      {
        dropChain(c);
        ++report.piecesDropped;
      }
      else
        spursAt[c.end].push_back(std::move(c));
    }
    for (std::size_t b = 0; b < f_.points.size(); ++b)
    {
      auto& spurs = spursAt[b];
      if (spurs.empty())
        continue;
      if (spurs.size() == deg_[b])
      {
        // keep the longest
        auto longest = std::max_element(spurs.begin(), spurs.end(),
          [](const Chain& x, const Chain& y) { return x.length < y.length; });
        spurs.erase(longest);
      }
      for (const Chain& c : spurs)
        dropChain(c);
      report.spursDropped += spurs.size();
    }
  }

  /// Separate loops (every point of degree 2) shorter than s.
  void dropLoops(double s, FeatureNetworkReport& report)
  {
    for (std::size_t i = 0; i < f_.segments.size(); ++i)
    {
      const int v = f_.segments[i][0];
      if (seen_[i] || deg_[v] != 2)
        continue;
      Chain c = walk(v, i);
      if (c.end < 0 && c.length < s)
      {
        dropChain(c);
        ++report.piecesDropped;
      }
    }
  }

  bool dropped(std::size_t segment) const { return drop_[segment] != 0; }

private:
  /// The chain from `v` through `first` to the next point of degree other than 2 (marked seen).
  Chain walk(int v, std::size_t first)
  {
    Chain c;
    const int start = v;
    for (std::size_t seg = first;;)
    {
      c.segs.push_back(seg);
      seen_[seg] = 1;
      c.length += f_.length(seg);
      v = f_.segments[seg][0] == v ? f_.segments[seg][1] : f_.segments[seg][0];
      if (deg_[v] != 2)
        return c.end = v, c;
      if (v == start)
        return c;
      seg = inc_[v][0] == seg ? inc_[v][1] : inc_[v][0];
    }
  }

  void dropChain(const Chain& c)
  {
    for (std::size_t seg : c.segs)
      drop_[seg] = 1;
  }

  const FeatureSegments& f_;
  const std::vector<std::size_t> deg_;
  const std::vector<std::vector<std::size_t>> inc_;
  std::vector<char> drop_, seen_;
};

/// Step 3: whiskers and small separate pieces. Chains run between points of degree other than 2.
void dropSpurs(FeatureSegments& f, double s, FeatureNetworkReport& report)
{
  SpurRemoval removal(f);
  removal.dropSpurs(s, report);
  removal.dropLoops(s, report);
  std::vector<char> keep(f.segments.size());
  for (std::size_t i = 0; i < f.segments.size(); ++i)
    keep[i] = !removal.dropped(i);
  if (std::find(keep.begin(), keep.end(), 0) != keep.end())
  {
    keepSegments(f, keep);
    keepUsedPoints(f);
  }
}

/// The lines without their separate pieces (connected parts) shorter than `s`, and the length of those.
std::pair<FeatureSegments, double> withoutShortPieces(const FeatureSegments& f, double s)
{
  UnionFind pieces(f.points.size());
  for (const auto& seg : f.segments)
    pieces.join(seg[0], seg[1]);
  std::vector<double> length(f.points.size(), 0.0);
  for (std::size_t i = 0; i < f.segments.size(); ++i)
    length[pieces.find(f.segments[i][0])] += f.length(i);
  FeatureSegments kept;
  kept.points = f.points;
  double dropped = 0.0;
  for (std::size_t i = 0; i < f.segments.size(); ++i)
    if (length[pieces.find(f.segments[i][0])] >= s)
      kept.segments.push_back(f.segments[i]);
    else
      dropped += f.length(i);
  return { kept, dropped };
}

/// Whether segment ab stays in the domain: every interior sample (at most h / 8 apart) lies in
/// it or within a thousandth of the segment's length of it (the mesher's own margin): along an
/// axis, or on a ring of 16 directions across the segment (on the edge of a box whose faces are a
/// little off the axes, as a welded soup's are, every axis probe may miss its wedge).
bool staysInDomain(const Vec3& a, const Vec3& b, const FeatureNetworkTolerances& tol)
{
  Vec3 u, v;
  perpendicularPair((1.0 / norm(b - a)) * (b - a), u, v);
  const auto near = [&](const Vec3& p, double eps) {
    if (tol.inDomain(p))
      return true;
    for (int axis = 0; axis < 3; ++axis)
      for (double sign : { -1.0, 1.0 })
      {
        Vec3 q = p;
        q[axis] += sign * eps;
        if (tol.inDomain(q))
          return true;
      }
    constexpr int kRing = 16;
    for (int k = 0; k < kRing; ++k)
    {
      const double phi = 2.0 * M_PI * (k + 0.5) / kRing;
      if (tol.inDomain(p + (eps * std::cos(phi)) * u + (eps * std::sin(phi)) * v))
        return true;
    }
    return false;
  };
  const double length = norm(b - a);
  const int n = std::max(3, static_cast<int>(std::ceil(8.0 * length / tol.edgeLength)));
  for (int k = 1; k < n; ++k)
    if (!near(lerp(a, b, static_cast<double>(k) / n), 1e-3 * length))
      return false;
  return true;
}

/// Step 6: a chord between two points of a noisy surface can pass outside it, where it cannot be a
/// mesh edge: segments that do not stay in the domain are dropped.
std::size_t dropSegmentsLeavingDomain(FeatureSegments& f, const FeatureNetworkTolerances& tol)
{
  std::vector<char> keep(f.segments.size());
  for (std::size_t s = 0; s < f.segments.size(); ++s)
    keep[s] = staysInDomain(f.points[f.segments[s][0]], f.points[f.segments[s][1]], tol);
  const std::size_t dropped = static_cast<std::size_t>(std::count(keep.begin(), keep.end(), 0));
  if (dropped)
  {
    keepSegments(f, keep);
    keepUsedPoints(f);
  }
  return dropped;
}

/// Whether the mesh can hold segment v->w at its end v: near v, the only vertices the segment
/// level leaves are segment points (refined points on the segments at v; facet points there are
/// refused as encroaching), so the cells at v have their circumcentres off the plane of two
/// segments at v (off the line of a lone one). Where the domain has no point there (probes at
/// `radius` off that plane, each side, straight and leaning towards the pair's bisector, for
/// every other segment at v; around the line of segments along one line; at a line's end, a quarter
/// of 12 probes around it, as a 90-degree edge has, since surface points near the end also take room) - a noise spike or thin fold that the segments cross or run along - no cell at v is in
/// the domain at any scale: the segment's first piece stays no mesh edge however often it is
/// split (the noisy spheres' pieces missing before, Benchmarks/noisy_features.py).
bool meshableEnd(const Vec3& v, const Vec3& w, const std::vector<Vec3>& others, double radius,
  const FeatureNetworkTolerances& tol)
{
  const Vec3 u = (1.0 / norm(w - v)) * (w - v);
  const Vec3 c = v + (0.25 * radius) * u;
  bool lone = true;
  for (const Vec3& o : others)
  {
    const Vec3 n = cross(u, o - v);
    if (norm(n) < 1e-6 * norm(o - v))
      continue; // along the same line: no plane
    lone = false;
    // off the plane, each side, straight and leaning 15 degrees towards the pair's bisector (where
    // a convex line of a flat face, e.g. a rim, has its 90-degree wedge)
    constexpr double kLean = 15.0 * M_PI / 180.0;
    const Vec3 off = (radius / norm(n)) * n;
    const Vec3 mid = u + (1.0 / norm(o - v)) * (o - v);
    const Vec3 in = norm(mid) > 1e-6 ? (radius / norm(mid)) * mid : Vec3{ 0, 0, 0 };
    for (double side : { -1.0, 1.0 })
      if (tol.inDomain(c + side * off) || tol.inDomain(c + std::cos(kLean) * side * off + std::sin(kLean) * in))
        return true;
    // A convex corner whose solid wedge the plane halves (a CAD part's chamfered tip) has no room
    // straight off the plane at this radius, but leaning 45-60 degrees towards the pair's bisector
    // it has, at the radius and at 4 times it: a wedge grows with the distance, a fold in the plane
    // does not. Only between segments of at least 2 h, as CAD edges are: the noisy spheres' chords
    // (at most h after resampling) lost pieces at such corners.
    if (std::min(norm(w - v), norm(o - v)) < 2.0 * tol.edgeLength)
      continue;
    for (double lean : { 45.0, 60.0 })
      for (double side : { -1.0, 1.0 })
      {
        const double a = lean * M_PI / 180.0;
        const Vec3 d = std::cos(a) * side * off + std::sin(a) * in;
        if (norm(in) > 0 && tol.inDomain(c + d) && tol.inDomain(c + 4.0 * d))
          return true;
      }
  }
  if (!lone)
    return false;
  const Vec3 t1 = std::abs(u.x) < 0.9 ? cross(u, Vec3{ 1, 0, 0 }) : cross(u, Vec3{ 0, 1, 0 });
  const Vec3 a = (1.0 / norm(t1)) * t1;
  const Vec3 b = cross(u, a);
  int inside = 0;
  for (int k = 0; k < 12; ++k)
  {
    const double angle = k * M_PI / 6.0;
    inside += tol.inDomain(c + radius * (std::cos(angle) * a + std::sin(angle) * b)) ? 1 : 0;
  }
  return inside >= (others.empty() ? 3 : 1);
}

/// Step 7: points where a segment end is no meshable end (meshableEnd) leave the lines: a point
/// of two segments is bypassed by the chord of its neighbours where that chord stays in the
/// domain (the spike is noise on the line), else, as at other points, the segments that cannot
/// end there are dropped. Rounds until none is left (at most `rounds`); returns the points removed.
std::size_t removeUnmeshableEnds(FeatureSegments& f, const FeatureNetworkTolerances& tol, int rounds = 8)
{
  std::size_t removed = 0;
  for (int r = 0; r < rounds; ++r)
  {
    const auto adjacent = neighbours(f);
    std::vector<char> drop(f.segments.size(), 0), bypassed(f.points.size(), 0);
    std::vector<std::array<int, 2>> added;
    std::vector<int> addedSource; // a bypass comes from the longer of the two segments it replaces
    std::size_t found = 0;
    for (std::size_t v = 0; v < f.points.size(); ++v)
    {
      const auto& n = adjacent[v];
      if (n.empty())
        continue;
      double shortest = std::numeric_limits<double>::infinity();
      for (int w : n)
        shortest = std::min(shortest, norm(f.points[w] - f.points[v]));
      const double radius = std::min(0.02 * tol.edgeLength, 0.25 * shortest);
      std::vector<int> bad;
      for (int w : n)
      {
        std::vector<Vec3> others;
        for (int o : n)
          if (o != w)
            others.push_back(f.points[o]);
        if (!meshableEnd(f.points[v], f.points[w], others, radius, tol))
          bad.push_back(w);
      }
      if (bad.empty())
        continue;
      ++found;
      // neighbours not bypassed in this round, so that the bypasses are independent
      const bool free = std::none_of(n.begin(), n.end(), [&](int w) { return bypassed[w] != 0; });
      const bool bypass = n.size() == 2 && free && !bypassed[v] && staysInDomain(f.points[n[0]], f.points[n[1]], tol);
      if (bypass)
      {
        bypassed[v] = 1;
        added.push_back({ n[0], n[1] });
        bad = n;
      }
      std::vector<std::size_t> replaced;
      for (std::size_t s = 0; s < f.segments.size(); ++s)
        for (int w : bad)
          if ((f.segments[s][0] == static_cast<int>(v) && f.segments[s][1] == w) ||
            (f.segments[s][1] == static_cast<int>(v) && f.segments[s][0] == w))
          {
            drop[s] = 1;
            replaced.push_back(s);
          }
      if (bypass && !f.source.empty())
        addedSource.push_back(f.sourceOfMost(replaced));
    }
    if (!found)
      break;
    for (char& d : drop)
      d = !d;
    keepSegments(f, drop);
    f.segments.insert(f.segments.end(), added.begin(), added.end());
    if (!f.source.empty())
      f.source.insert(f.source.end(), addedSource.begin(), addedSource.end());
    removed += found;
    mergeFeatureSegments(f);
    keepUsedPoints(f);
  }
  return removed;
}

double shortestSegment(const FeatureSegments& f)
{
  double shortest = f.segments.empty() ? 0.0 : std::numeric_limits<double>::infinity();
  for (std::size_t s = 0; s < f.segments.size(); ++s)
    shortest = std::min(shortest, f.length(s));
  return shortest;
}
}

double featureLinesDistance(const FeatureSegments& from, const FeatureSegments& to, double spacing)
{
  if (from.empty())
    return 0.0;
  if (to.empty())
    return std::numeric_limits<double>::infinity();
  const std::vector<Segment> segs = cgalSegments(to);
  Tree tree(segs.begin(), segs.end());
  tree.accelerate_distance_queries();
  double worst = 0.0;
  for (std::size_t s = 0; s < from.segments.size(); ++s)
  {
    const Vec3& a = from.points[from.segments[s][0]];
    const Vec3& b = from.points[from.segments[s][1]];
    const int n = std::max(1, static_cast<int>(std::ceil(from.length(s) / spacing)));
    for (int k = 0; k <= n; ++k)
      worst = std::max(worst, tree.squared_distance(toPoint(lerp(a, b, static_cast<double>(k) / n))));
  }
  return std::sqrt(worst);
}

FeatureNetworkReport simplifyFeatureNetwork(FeatureSegments& f, const FeatureNetworkTolerances& tol)
{
  FeatureNetworkReport report;
  const double h = tol.edgeLength;
  const FeatureSegments given = f;
  // Own edge sizes go with the sources, which every step carries (two lines' sizes on one segment
  // are no contradiction here, as mergeFeatureSegments takes them for a given line).
  f.edgeSizes.clear();
  f.source.resize(f.segments.size());
  std::iota(f.source.begin(), f.source.end(), 0);
  const auto sizesFromSources = [&] {
    if (!given.edgeSizes.empty())
      for (int s : f.source)
        f.edgeSizes.push_back(given.edgeSize(static_cast<std::size_t>(s)));
  };
  if (f.empty() || !(h > 0))
  {
    sizesFromSources();
    return report;
  }
  const double d = tol.mergeDistance();
  const DeviationBound bound(given, tol.maxDeviation, tol.minAngle);
  if (d > 0)
  {
    report.pointsMerged = mergeNearbyPoints(f, d, bound);
    report.pointsSnapped = snapUntilStable(f, d, tol.minAngle, bound);
  }
  if (tol.spurLength() > 0)
    dropSpurs(f, tol.spurLength(), report);
  report.pointsResampled = resampleFeatureLines(f, h, std::max(0.0, tol.chordTolerance));
  if (d > 0)
    report.pointsSnapped += snapUntilStable(f, d, tol.minAngle, bound);
  if (tol.inDomain)
  {
    report.segmentsOutside = dropSegmentsLeavingDomain(f, tol);
    report.unmeshableEnds = removeUnmeshableEnds(f, tol);
    if ((report.segmentsOutside || report.unmeshableEnds) && tol.spurLength() > 0)
      dropSpurs(f, tol.spurLength(), report);
  }
  // Separate pieces shorter than the spur length are dropped on purpose: measured apart.
  const auto [kept, shortLength] = withoutShortPieces(given, tol.spurLength());
  report.shortPiecesLength = shortLength;
  report.givenToSimplified = featureLinesDistance(kept, f, h / 50.0);
  report.simplifiedToGiven = featureLinesDistance(f, given, h / 50.0);
  report.smallestAngle = f.smallestAngle();
  report.shortestSegment = shortestSegment(f);
  sizesFromSources();
  return report;
}
}
