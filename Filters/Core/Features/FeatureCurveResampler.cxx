// SPDX-License-Identifier: GPL-3.0-or-later
#include "FeatureCurveResampler.h"

#include "FeatureCurveLengths.h"

#include <algorithm>
#include <utility>

namespace omesh::featurelines
{
namespace
{
/// How far the curve may bulge between two consecutive found points of `piece` (which lie on it):
/// the largest sagitta s^2 / (8 R), s the longer step at a vertex, R the radius of the circle through
/// it and its two neighbours, at vertices turning by at most `cornerAngle` degrees (corners stay
/// vertices) between steps of about one length. A chord kept within the tolerance of the found points can miss the curve between them
/// by this much more (0.046 for 0.0375 on the screw's entry curve).
double bulgeBetweenSamples(const FeatureSegments& piece, double cornerAngle)
{
  std::vector<std::vector<int>> next(piece.points.size());
  for (const auto& s : piece.segments)
  {
    next[s[0]].push_back(s[1]);
    next[s[1]].push_back(s[0]);
  }
  double bulge = 0.0;
  for (size_t v = 0; v < next.size(); ++v)
  {
    if (next[v].size() != 2)
      continue;
    const Vec3 &x = piece.points[v], &p = piece.points[next[v][0]], &q = piece.points[next[v][1]];
    const double a = norm(p - x), b = norm(q - x), c = norm(q - p);
    const double twiceArea = norm(cross(p - x, q - x));
    // straight, a corner, or uneven steps (a vertex moved onto a crossing or a junction next to
    // it: over the short step the circle through the three points says little of the curve)
    if (twiceArea <= 0.0 || 180.0 - angleAt(x, p, q) > cornerAngle || std::min(a, b) < 0.5 * std::max(a, b))
      continue;
    const double radius = a * b * c / (2.0 * twiceArea);
    const double step = std::max(a, b);
    bulge = std::max(bulge, step * step / (8.0 * radius));
  }
  return bulge;
}

/// The points of a resampled single curve in order (a closed one repeats its first point).
std::vector<int> chainOrder(const FeatureSegments& f)
{
  std::vector<std::vector<int>> inc(f.points.size());
  for (size_t s = 0; s < f.segments.size(); ++s)
    for (int v : f.segments[s])
      inc[v].push_back(static_cast<int>(s));
  int start = 0;
  for (size_t v = 0; v < inc.size(); ++v)
    if (inc[v].size() == 1)
    {
      start = static_cast<int>(v);
      break;
    }
  std::vector<int> chain{ start };
  std::vector<char> used(f.segments.size(), 0);
  for (int v = start;;)
  {
    int next = -1;
    for (int s : inc[v])
      if (!used[s])
      {
        used[s] = 1;
        next = f.segments[s][0] == v ? f.segments[s][1] : f.segments[s][0];
        break;
      }
    if (next < 0)
      break;
    chain.push_back(next);
    v = next;
  }
  return chain;
}

/// Of the points `inner` (in order from a to b), those a polyline from a to b needs so that every
/// one of them lies within `tolerance` of it: the farthest from the chord first, recursively
/// (Douglas-Peucker).
std::vector<Vec3> bendsBeyond(const Vec3& a, const Vec3& b, const std::vector<Vec3>& inner, double tolerance)
{
  size_t far = inner.size();
  double farthest = tolerance;
  for (size_t i = 0; i < inner.size(); ++i)
    if (const double d = distanceToSegment(inner[i], a, b); d > farthest)
    {
      farthest = d;
      far = i;
    }
  if (far == inner.size())
    return {};
  std::vector<Vec3> out = bendsBeyond(a, inner[far], { inner.begin(), inner.begin() + far }, tolerance);
  out.push_back(inner[far]);
  const std::vector<Vec3> after = bendsBeyond(inner[far], b, { inner.begin() + far + 1, inner.end() }, tolerance);
  out.insert(out.end(), after.begin(), after.end());
  return out;
}
}

FeatureCurveResampler::FeatureCurveResampler(
  const FeatureLineOptions& options, const FeatureCurveLocator& locator, FeatureLines& result)
  : options_(options)
  , locator_(locator)
  , result_(result)
{
}

void FeatureCurveResampler::addCurves(
  const FeatureCurveGraph& graph, const std::vector<Crossing>& crossings, const std::vector<std::vector<int>>& chains)
{
  std::map<int, int> sharedPoint; // graph node -> point of result.segments
  for (const auto& chain : chains)
    addCurve(graph, crossings, chain, sharedPoint);
}

const Signature* FeatureCurveResampler::signatureOf(int line) const
{
  const auto it = signature_.find(line);
  return it != signature_.end() ? &it->second : nullptr;
}

void FeatureCurveResampler::addCurve(const FeatureCurveGraph& graph, const std::vector<Crossing>& crossings,
  const std::vector<int>& chain, std::map<int, int>& sharedPoint)
{
  if (chain.size() < 2)
    return;
  const int crossingCount = graph.crossingCount();
  const int tagged = graph.tagOf(chain);
  if (tagged >= crossingCount)
    return; // two junctions joined directly: no crossing tells the regions (does not happen)
  FeatureLine line;
  line.materials = materialsOf(crossings[tagged].regions);
  line.triple = line.materials.size() >= 3;
  // A loop through a junction stays open there, so the junction is kept as its two ends.
  const bool closed = chain.back() == chain.front() && graph.adjacent(chain.front()).size() == 2 && chain.front() < crossingCount;
  const size_t m = closed ? chain.size() - 1 : chain.size();
  if (closed && m < 3)
    return;
  std::vector<Vec3> points;
  for (size_t k = 0; k < m; ++k)
    points.push_back(graph.nodes()[chain[k]]);
  const Signature regions = crossings[tagged].regions;
  // the result's point of a graph node, shared by the curves that end there
  const auto pointOfNode = [&](int node) {
    auto [it, added] = sharedPoint.emplace(node, static_cast<int>(result_.segments.points.size()));
    if (added)
      result_.segments.points.push_back(graph.nodes()[node]);
    return it->second;
  };
  addResampledCurve(std::move(line), std::move(points), closed,
    [&](int end) { return pointOfNode(end == 0 ? chain.front() : chain.back()); }, &regions);
}

void FeatureCurveResampler::addResampledCurve(FeatureLine line, std::vector<Vec3> points, bool closed,
  const std::function<int(int)>& endPoint, const Signature* regions)
{
  const size_t m = points.size();
  FeatureSegments piece;
  piece.points = std::move(points);
  for (size_t k = 0; k + 1 < m; ++k)
    piece.segments.push_back({ static_cast<int>(k), static_cast<int>(k + 1) });
  if (closed)
    piece.segments.push_back({ static_cast<int>(m - 1), 0 });
  const Vec3 first = piece.points.front();
  resampleCurve(piece, line.materials, line.crease);
  std::vector<int> order = chainOrder(piece);
  if (!closed && norm(piece.points[order.front()] - first) > 0)
    std::reverse(order.begin(), order.end());
  const bool repeatsFirst = closed && order.size() > 1 && order.back() == order.front();
  std::vector<Vec3> along;
  for (int v : order)
    along.push_back(piece.points[v]);
  if (regions)
    along = onCurve(along, *regions, toleranceFor(options_, line.materials, lengthFor(options_, line.materials)));
  for (size_t k = 0; k < along.size(); ++k)
  {
    if (!closed && (k == 0 || k + 1 == along.size()))
      line.points.push_back(endPoint(k == 0 ? 0 : 1));
    else if (repeatsFirst && k + 1 == along.size())
      line.points.push_back(line.points.front());
    else
    {
      line.points.push_back(static_cast<int>(result_.segments.points.size()));
      result_.segments.points.push_back(along[k]);
    }
  }
  for (size_t k = 0; k + 1 < line.points.size(); ++k)
    if (line.points[k] != line.points[k + 1])
      result_.segments.segments.push_back({ line.points[k], line.points[k + 1] });
  if (regions)
    signature_.emplace(static_cast<int>(result_.lines.size()), *regions);
  result_.lines.push_back(std::move(line));
}

void FeatureCurveResampler::splitOnCurve(
  const Vec3& a, const Vec3& b, const Signature& regions, double tolerance, int depth, std::vector<Vec3>& out) const
{
  Crossing m;
  if (depth > 0 && locator_.curveBetween(a, b, regions, m) && norm(m.point - 0.5 * (a + b)) > tolerance)
  {
    splitOnCurve(a, m.point, regions, tolerance, depth - 1, out);
    out.push_back(m.point);
    splitOnCurve(m.point, b, regions, tolerance, depth - 1, out);
  }
}

/// At the chord length of the curve's materials (chordLengthFor; no segment length: left as found), within
/// the smallest of their chord tolerances of the curve: of the found points, less what the curve
/// bulges between them (at most three quarters of the tolerance is given up to that).
void FeatureCurveResampler::resampleCurve(FeatureSegments& piece, const std::vector<int>& materials, bool crease) const
{
  const double length = lengthFor(options_, materials);
  if (length <= 0)
    return;
  const double tolerance = toleranceFor(options_, materials, length);
  resampleFeatureLines(piece, chordLengthFor(options_, materials, crease),
    std::max(tolerance - bulgeBetweenSamples(piece, options_.smallAngle), 0.25 * tolerance), options_.smallAngle);
}

/// The chain `along` with the curve's own points inserted where a chord's midpoint lies farther
/// than `tolerance` from the curve (the crossing in the plane halfway, as refine does), down to
/// chords within it: resampling alone keeps the chords near the found points only, and a chord
/// off its interfaces by more than their facets' tolerance leaves the mesher a gap between the
/// segment and the surfaces through the curve, which it fills with ever smaller cells (at a tight
/// radius-edge bound, a triple line met at a grazing angle).
std::vector<Vec3> FeatureCurveResampler::onCurve(const std::vector<Vec3>& along, const Signature& regions, double tolerance) const
{
  std::vector<Vec3> out;
  if (along.empty())
    return out;
  const std::vector<Vec3> chain = withBends(along, regions, tolerance);
  if (!(tolerance > 0))
    return chain;
  out.push_back(chain.front());
  for (size_t k = 0; k + 1 < chain.size(); ++k)
  {
    splitOnCurve(chain[k], chain[k + 1], regions, tolerance, 8, out);
    out.push_back(chain[k + 1]);
  }
  return out;
}

/// The chain `along` (its points on the curve) with the points where the curve crosses the
/// domains' bend planes (Domain::bendPlanes: a label map's cell planes, where its interfaces and
/// so the curve turn) located on the curve to the search's precision: an inner point within a
/// quarter chord of one is moved onto it, else it is inserted where the chord would pass it
/// farther than `tolerance` (the bends the chord misses most first, as Douglas-Peucker, until
/// every bend lies within it; none when `tolerance` is not positive: all of them). The search
/// keeps corners to a 256th of a grid step, which leaves chords beside the interfaces next to
/// them: the midpoint splits alone can run a tight radius-edge bound into the vertex budget. Not
/// every bend as a vertex: that would cut a bone rim on a voxel staircase at each cell plane
/// (chords a few times shorter than its tolerance), and the mesh would grade down to them.
std::vector<Vec3> FeatureCurveResampler::withBends(const std::vector<Vec3>& along, const Signature& regions, double tolerance) const
{
  std::vector<Vec3> out{ along.front() };
  std::vector<BendPlane> planes;
  for (size_t k = 0; k + 1 < along.size(); ++k)
  {
    const Vec3 a = out.back();
    Vec3 b = along[k + 1];
    const double L = norm(b - a);
    planes.clear();
    if (L > 4 * locator_.precision())
      for (const auto& d : locator_.oracle().domains())
        d->bendPlanes(a, b, planes);
    std::vector<std::pair<double, Vec3>> bends; // (distance from a, point on the curve)
    for (const BendPlane& plane : planes)
    {
      Crossing m;
      if (locator_.curveInPlane(plane, L, regions, m))
        bends.emplace_back(norm(m.point - a), m.point);
    }
    std::sort(bends.begin(), bends.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
    const bool aMoves = out.size() > 1, bMoves = k + 2 < along.size();
    std::vector<Vec3> inner; // bends that would be new vertices
    for (const auto& [unused, x] : bends)
    {
      const double toA = norm(x - out.back()), toB = norm(x - b);
      if (toA < 0.25 * L && aMoves)
        out.back() = x;
      else if (toB < 0.25 * L && bMoves)
        b = x;
      else if (toA > 0.25 * L && toB > 0.25 * L)
        inner.push_back(x);
    }
    // each turn within half the tolerance of the chords, the other half left to the chords
    // between the points found (kept to the whole tolerance, 150 against 124 of ~5,000 found
    // segments read beyond a tenth of the facet distance on the generated bone cases,
    // Benchmarks/found_line_fidelity.py)
    if (tolerance > 0)
      inner = bendsBeyond(out.back(), b, inner, 0.5 * tolerance);
    out.insert(out.end(), inner.begin(), inner.end());
    out.push_back(b);
  }
  return out;
}
}
