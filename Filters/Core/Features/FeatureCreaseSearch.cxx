// SPDX-License-Identifier: GPL-3.0-or-later
#include "FeatureCreaseSearch.h"

#include "FeatureCurveLengths.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <set>

namespace omesh::featurelines
{
FeatureCreaseSearch::FeatureCreaseSearch(const HierarchicalOracle& oracle, const FeatureLineOptions& options,
  double spacing, double diagonal, FeatureCurveResampler& resampler, FeatureLines& result)
  : oracle_(oracle)
  , options_(options)
  , resampler_(resampler)
  , result_(result)
  , h_(spacing)
  , probe_(1e-7 * diagonal)
{
}

void FeatureCreaseSearch::addCreases()
{
  if (options_.creaseAngle >= 180.0)
    return; // no faces' normals differ by more than 180 degrees: creases off
  std::vector<CreasePiece> pieces;
  const auto& domains = oracle_.domains();
  for (size_t i = 0; i < domains.size(); ++i)
    for (const Crease& c : domains[i]->creases(options_.creaseAngle, 1e-3 * h_))
      visiblePieces(static_cast<int>(i), c, pieces);
  // the ends first, while result_ holds the found curves only: one that enters another input
  // lies on the curve found there (within the grid step the chords keep to); the crease's own
  // end (a box's corner) joins a curve only when that curve has a corner right there (the
  // search keeps corners to 1/256 of a step: a tray's bottom corner on the cut plane's rim)
  for (CreasePiece& piece : pieces)
    if (!piece.closed)
      for (int end = 0; end < 2; ++end)
      {
        const Vec3& x = end ? piece.points.back() : piece.points.front();
        // Where the crease's materials change (another input's exact crossing: outside/implant
        // before, bone/implant after), the three meet: x is a point of the curve of all of them,
        // which must pass through it. The grid does not see that curve closer than a step to
        // another piece of itself: a triple line touching the crease at a grazing angle is a V
        // with its tip on x (bbox_centre_on_face: arms 12 degrees apart, the corner cut 0.8 mm
        // short of the crease, the tip shared by no curve), so that curve is looked for farther.
        std::vector<int> meeting;
        if (!piece.across[end].empty() && piece.across[end] != piece.materials)
          std::set_union(piece.materials.begin(), piece.materials.end(), piece.across[end].begin(),
            piece.across[end].end(), std::back_inserter(meeting));
        piece.endPoint[end] = meeting.size() >= 3 ? meetingVertex(x, meeting) : -1;
        if (piece.endPoint[end] < 0)
          piece.endPoint[end] = endVertex(x, piece.entering[end] ? h_ : h_ / 64);
      }
  for (const CreasePiece& piece : pieces)
    addCreasePiece(piece);
}

/// Who is seen beside the crease at m (on chord ab): the input (domain `owner`) must decide the
/// material on its side (probed along the inward bisector of the faces' normals, which way is
/// inside asked of the input itself) and another material must lie across (the outward
/// bisector). Empty: not seen, or three materials around it (a ring of probes): then it is a
/// triple line the search finds (a tray's bottom edge on the cut plane over the bone).
std::vector<int> FeatureCreaseSearch::seenAt(
  int owner, const Vec3& m, const Vec3& a, const Vec3& b, const std::array<Vec3, 2>& n) const
{
  const Vec3 t = (1.0 / norm(b - a)) * (b - a);
  Vec3 s = n[0] + n[1];
  s = s - dot(s, t) * t;
  if (!(norm(s) > 1e-6))
    return {};
  s = (1.0 / norm(s)) * s;
  const Vec3 step = probe_ * s;
  const Domain& d = *oracle_.domains()[owner];
  const bool plus = d.material(m + step) != kOutside, minus = d.material(m - step) != kOutside;
  if (plus == minus)
    return {};
  const Vec3 in = plus ? m + step : m - step, out = plus ? m - step : m + step;
  const Decision mine = oracle_.decide(in);
  const int across = oracle_.material(out);
  if (mine.domain != owner || across == mine.material)
    return {};
  const Vec3 s2 = cross(t, s);
  std::set<int> around{ mine.material, across };
  for (int k = 0; k < 16 && around.size() < 3; ++k)
    around.insert(oracle_.material(m + probe_ * (std::cos(k * M_PI / 8) * s + std::sin(k * M_PI / 8) * s2)));
  if (around.size() >= 3)
    return {};
  return { std::min(mine.material, across), std::max(mine.material, across) };
}

void FeatureCreaseSearch::visiblePieces(int owner, const Crease& c, std::vector<CreasePiece>& pieces) const
{
  // stations along the crease: its points and the other inputs' crossings, each with the
  // materials seen on the stretch to the next one
  std::vector<Vec3> at;
  std::vector<std::vector<int>> seen;
  std::vector<char> entry; // the station is a crossing of another input
  for (size_t k = 0; k + 1 < c.points.size(); ++k)
  {
    const Vec3 a = c.points[k], b = c.points[k + 1];
    if (!(norm(b - a) > 0))
      continue;
    std::vector<double> ts{ 0.0, 1.0 };
    for (size_t j = 0; j < oracle_.domains().size(); ++j)
      if (static_cast<int>(j) != owner)
        oracle_.domains()[j]->crossings(a, b, ts);
    std::sort(ts.begin(), ts.end());
    for (size_t q = 0; q + 1 < ts.size(); ++q)
    {
      if (!(ts[q + 1] - ts[q] > 1e-12) && !(q == 0 && ts.size() == 2))
        continue;
      at.push_back(ts[q] == 0.0 ? a : lerp(a, b, ts[q]));
      entry.push_back(ts[q] > 0.0);
      seen.push_back(seenAt(owner, lerp(a, b, 0.5 * (ts[q] + ts[q + 1])), a, b, c.normals[k]));
    }
  }
  if (seen.empty())
    return;
  at.push_back(c.points.back());
  entry.push_back(0);
  std::vector<CreasePiece> runs;
  std::vector<std::array<size_t, 2>> span;
  for (size_t q = 0; q < seen.size();)
  {
    size_t r = q + 1;
    while (r < seen.size() && seen[r] == seen[q])
      ++r;
    if (!seen[q].empty())
    {
      CreasePiece p;
      p.materials = seen[q];
      p.points.assign(at.begin() + static_cast<long>(q), at.begin() + static_cast<long>(r) + 1);
      p.entering[0] = entry[q];
      p.entering[1] = entry[r];
      if (q > 0)
        p.across[0] = seen[q - 1];
      if (r < seen.size())
        p.across[1] = seen[r];
      runs.push_back(std::move(p));
      span.push_back({ q, r });
    }
    q = r;
  }
  if (c.closed() && !runs.empty() && span.front()[0] == 0 && span.back()[1] == seen.size())
  {
    if (runs.size() == 1)
      runs[0].closed = true; // seen all around
    else if (runs.front().materials == runs.back().materials)
    { // the last piece runs on through the crease's first point
      CreasePiece& last = runs.back();
      last.points.insert(last.points.end(), runs.front().points.begin() + 1, runs.front().points.end());
      last.entering[1] = runs.front().entering[1];
      last.across[1] = runs.front().across[1];
      runs.erase(runs.begin());
    }
  }
  for (CreasePiece& p : runs)
  {
    double length = 0.0;
    for (size_t k = 0; k + 1 < p.points.size(); ++k)
      length += norm(p.points[k + 1] - p.points[k]);
    // a crease peeking out of another input for less than a grid step: the curve found there runs
    // within that of it (as for curves found, shorter ones are not kept)
    if ((p.entering[0] || p.entering[1]) && length < 0.5 * h_)
      continue;
    pieces.push_back(std::move(p));
  }
}

/// Whether `line` turns at its k-th point by more than the corner angle of resampling (or ends
/// there): the search's corner of a curve that turns where a crease meets it, the crease's end
/// the true one. (Split there instead, the curve kept a piece from the search's corner to the
/// true one: 0.034 of a 0.75 chord where a box's edge leaves a ball, and the trims at the
/// junction, a third of its shortest piece, cut every line there down to 0.011.)
bool FeatureCreaseSearch::turnsAt(const FeatureLine& line, size_t k) const
{
  const auto& S = result_.segments;
  const bool loop = line.points.size() > 2 && line.points.front() == line.points.back();
  const size_t n = line.points.size();
  if (!loop && (k == 0 || k + 1 == n))
    return true;
  const size_t prev = k > 0 ? k - 1 : n - 2, next = k + 1 < n ? k + 1 : 1;
  return angleAt(S.points[line.points[k]], S.points[line.points[prev]], S.points[line.points[next]]) <
    180.0 - options_.smallAngle;
}

/// The vertex of a crease's end x where the crease's materials change, so all of `meeting` meet
/// there: x becomes a vertex of the nearest curve found with all those materials (within
/// kMeetingReach grid steps; -1: none), its nearest vertex moved onto x when within h/64 (the
/// curve's own corner there), else its nearest chord split at x and the two new chords put back
/// on the curve (onCurve's midpoint splits, as the curve's other chords).
int FeatureCreaseSearch::meetingVertex(const Vec3& x, const std::vector<int>& meeting)
{
  if (auto it = creasePoint_.find(key(x)); it != creasePoint_.end())
    return it->second;
  auto& S = result_.segments;
  int bestLine = -1;
  size_t bestK = 0;
  double nearest = kMeetingReach * h_;
  for (size_t l = 0; l < result_.lines.size(); ++l)
  {
    const FeatureLine& line = result_.lines[l];
    if (!std::includes(line.materials.begin(), line.materials.end(), meeting.begin(), meeting.end()))
      continue;
    for (size_t k = 0; k + 1 < line.points.size(); ++k)
      if (const double d = distanceToSegment(x, S.points[line.points[k]], S.points[line.points[k + 1]]); d < nearest)
      {
        nearest = d;
        bestLine = static_cast<int>(l);
        bestK = k;
      }
  }
  if (bestLine < 0)
    return -1;
  FeatureLine& line = result_.lines[bestLine];
  const int a = line.points[bestK], b = line.points[bestK + 1];
  int v = -1;
  const double da = norm(S.points[a] - x), db = norm(S.points[b] - x), closer = std::min(da, db);
  if (closer <= h_ / 64 ||
    (closer <= 0.25 * norm(S.points[b] - S.points[a]) && turnsAt(line, da <= db ? bestK : bestK + 1)))
  {
    v = da <= db ? a : b;
    S.points[v] = x;
  }
  else
  {
    // a -> (on the curve) -> x -> (on the curve) -> b, replacing the chord ab
    std::vector<Vec3> inner;
    const Signature* regions = resampler_.signatureOf(bestLine);
    const double tolerance = toleranceFor(options_, line.materials, lengthFor(options_, line.materials));
    if (regions && tolerance > 0)
      resampler_.splitOnCurve(S.points[a], x, *regions, tolerance, 8, inner);
    const size_t before = inner.size();
    inner.push_back(x);
    if (regions && tolerance > 0)
      resampler_.splitOnCurve(x, S.points[b], *regions, tolerance, 8, inner);
    std::vector<int> ids;
    for (size_t k = 0; k < inner.size(); ++k)
    {
      ids.push_back(static_cast<int>(S.points.size()));
      S.points.push_back(inner[k]);
    }
    v = ids[before];
    for (auto& seg : S.segments)
      if ((seg[0] == a && seg[1] == b) || (seg[0] == b && seg[1] == a))
      {
        const bool forward = seg[0] == a;
        std::vector<int> chain{ a };
        chain.insert(chain.end(), ids.begin(), ids.end());
        chain.push_back(b);
        if (!forward)
          std::reverse(chain.begin(), chain.end());
        seg[1] = chain[1];
        for (size_t k = 1; k + 1 < chain.size(); ++k)
          S.segments.push_back({ chain[k], chain[k + 1] });
        break;
      }
    line.points.insert(line.points.begin() + static_cast<long>(bestK) + 1, ids.begin(), ids.end());
  }
  creasePoint_.emplace(key(x), v);
  return v;
}

/// The vertex of a crease's end x (the same point for every crease ending there: a box's corner).
/// When a curve found passes within `reach`, x becomes a vertex of it: its nearest segment's end
/// is moved onto x when within a quarter of that segment (a corner the search kept to 1/256 of a
/// step), else the segment is split at x.
int FeatureCreaseSearch::endVertex(const Vec3& x, double reach)
{
  if (auto it = creasePoint_.find(key(x)); it != creasePoint_.end())
    return it->second;
  auto& S = result_.segments;
  int best = -1;
  double nearest = reach;
  for (size_t s = 0; s < S.segments.size(); ++s)
  {
    if (const double dist = distanceToSegment(x, S.points[S.segments[s][0]], S.points[S.segments[s][1]]); dist < nearest)
    {
      nearest = dist;
      best = static_cast<int>(s);
    }
  }
  int v = -1;
  if (best >= 0)
  {
    auto& seg = S.segments[best];
    const double quarter = 0.25 * norm(S.points[seg[1]] - S.points[seg[0]]);
    const double d0 = norm(S.points[seg[0]] - x), d1 = norm(S.points[seg[1]] - x);
    if (std::min(d0, d1) <= quarter)
    {
      v = d0 <= d1 ? seg[0] : seg[1];
      S.points[v] = x;
    }
    else
    {
      v = static_cast<int>(S.points.size());
      S.points.push_back(x);
      const int a = seg[0], b = seg[1];
      seg[1] = v;
      S.segments.push_back({ v, b });
      for (FeatureLine& l : result_.lines)
        for (size_t k = 0; k + 1 < l.points.size(); ++k)
          if ((l.points[k] == a && l.points[k + 1] == b) || (l.points[k] == b && l.points[k + 1] == a))
          {
            l.points.insert(l.points.begin() + static_cast<long>(k) + 1, v);
            k = l.points.size(); // one occurrence per line
          }
    }
  }
  else
  {
    v = static_cast<int>(S.points.size());
    S.points.push_back(x);
  }
  creasePoint_.emplace(key(x), v);
  return v;
}

void FeatureCreaseSearch::addCreasePiece(const CreasePiece& p)
{
  FeatureLine line;
  line.materials = p.materials;
  line.triple = line.materials.size() >= 3;
  line.crease = true;
  const size_t m = p.closed ? p.points.size() - 1 : p.points.size();
  resampler_.addResampledCurve(std::move(line), std::vector<Vec3>(p.points.begin(), p.points.begin() + static_cast<long>(m)),
    p.closed, [&](int end) { return p.endPoint[end]; });
}
}
