// SPDX-License-Identifier: GPL-3.0-or-later
#include "OracleFeatureLines.h"

#include "Domain.h"
#include "HierarchicalOracle.h"
#include "InputError.h"

#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <map>
#include <set>
#include <sstream>
#include <unordered_map>

namespace omesh
{
namespace
{
using Region = Decision;
using Signature = std::vector<Region>; // the regions around a curve, sorted

/// The regions met along a segment: r[0] up to t[0], r[1] up to t[1], ..., r.back() up to 1.
struct EdgeRegions
{
  std::vector<double> t;
  std::vector<Region> r;
};

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

/// Exact: every domain lists where its material may change, and the region is evaluated between
/// consecutive candidates (as HierarchicalOracle::intersect does).
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

/// A rectangle o + s U + t V (s, t in [0, 1]) with the regions along its four edges; bottom and top
/// run along U, left and right along V.
struct Rect
{
  Vec3 o, U, V;
  EdgeRegions bottom, top, left, right;
};

/// The regions met walking once around the rectangle, consecutive repeats merged.
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

/// A curve where regions meet passes through the rectangle when some boundary between two regions
/// crosses its edges an odd number of times (a boundary that only enters and leaves crosses twice).
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

struct Crossing
{
  Vec3 point;
  Signature regions;
};

/// Bisects a rectangle that holds a curve down to `precision`; the centre of the last one and the
/// regions around it.
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

/// The materials meeting at a curve, ascending.
std::vector<int> materialsOf(const Signature& s)
{
  std::vector<int> m;
  for (const Region& r : s)
    m.push_back(r.material);
  std::sort(m.begin(), m.end());
  m.erase(std::unique(m.begin(), m.end()), m.end());
  return m;
}

/// A curve is a feature when three or more materials meet there, or when the interfaces meeting
/// there belong to two different inputs' boundaries: the boundary between two regions of different
/// materials is the boundary of the higher-priority deciding domain of the two.
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

/// The point nearest (least squares) to lines through p[i] along unit d[i]; false when they are
/// (nearly) parallel.
bool nearestToLines(const std::vector<Vec3>& p, const std::vector<Vec3>& d, Vec3& x)
{
  double A[3][3] = {}, b[3] = {};
  for (size_t k = 0; k < p.size(); ++k)
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
      {
        const double m = (i == j ? 1.0 : 0.0) - d[k][i] * d[k][j];
        A[i][j] += m;
        b[i] += m * p[k][j];
      }
  const double det = A[0][0] * (A[1][1] * A[2][2] - A[1][2] * A[2][1]) -
    A[0][1] * (A[1][0] * A[2][2] - A[1][2] * A[2][0]) + A[0][2] * (A[1][0] * A[2][1] - A[1][1] * A[2][0]);
  if (!(std::abs(det) > 1e-6 * std::pow(static_cast<double>(p.size()), 3)))
    return false;
  for (int c = 0; c < 3; ++c)
  {
    double M[3][3];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        M[i][j] = j == c ? b[i] : A[i][j];
    x[c] = (M[0][0] * (M[1][1] * M[2][2] - M[1][2] * M[2][1]) - M[0][1] * (M[1][0] * M[2][2] - M[1][2] * M[2][0]) +
             M[0][2] * (M[1][0] * M[2][1] - M[1][1] * M[2][0])) /
      det;
  }
  return isFinite(x);
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

std::string describe(const Vec3& p)
{
  std::ostringstream o;
  o << "(" << p.x << ", " << p.y << ", " << p.z << ")";
  return o.str();
}

struct Link
{
  int a, b;
};

/// Sets of 0..n-1 joined pairwise; a set's root is its smallest member.
class SmallestRoot
{
public:
  explicit SmallestRoot(size_t n)
    : parent_(n)
  {
    for (size_t v = 0; v < n; ++v)
      parent_[v] = static_cast<int>(v);
  }
  int root(int v)
  {
    while (parent_[v] != v)
      v = parent_[v] = parent_[parent_[v]];
    return v;
  }
  void join(int a, int b)
  {
    a = root(a), b = root(b);
    if (a != b)
      parent_[std::max(a, b)] = std::min(a, b);
  }

private:
  std::vector<int> parent_;
};

/// Where curves meet: the centre of the cubes they end in and the crossings ending there.
struct Junction
{
  Vec3 centre;
  std::vector<int> ending;
};

/// findFeatureLines' state and steps: the search grid and the regions at its points, the grid
/// edges walked (cached: each is shared by four faces), the crossings found on grid faces and how
/// cubes link them, then the graph of crossings and junctions whose curves become the result.
class FeatureLineSearch
{
public:
  /// The grid: two steps of room around the materials, the spacing widened (with a warning) to
  /// stay within options.maximumGridPoints.
  FeatureLineSearch(const HierarchicalOracle& oracle, const FeatureLineOptions& options, FeatureLines& result)
    : oracle_(oracle)
    , options_(options)
    , result_(result)
  {
    const BoundingBox box = oracle.bounds(); // throws for an empty or unbounded oracle
    diagonal_ = norm(box.size());
    double h = options.spacing > 0 ? options.spacing
      : options.maxSegmentLength > 0 ? 0.5 * options.maxSegmentLength
                                     : diagonal_ / 64.0;
    h = std::min(h, diagonal_ / 4.0);
    if (!(h > 0) || !std::isfinite(h))
      throw InputError("feature lines: the search grid's spacing " + std::to_string(h) + " is not a positive number");
    // The origin is shifted by odd fractions of a step so that grid planes do not fall on the
    // round coordinates inputs like to have.
    const Vec3 shift{ 0.5 + 0.1234567, 0.5 + 0.2718282, 0.5 + 0.3141593 };
    auto gridSize = [&](double step) {
      std::array<int, 3> n;
      for (int i = 0; i < 3; ++i)
        n[i] = static_cast<int>(std::ceil(box.size()[i] / step + 2 * shift[i])) + 2;
      return n;
    };
    std::array<int, 3> n = gridSize(h);
    const double wanted = h;
    while (static_cast<double>(n[0]) * n[1] * n[2] > static_cast<double>(options.maximumGridPoints))
      n = gridSize(h *= 1.1);
    if (h > wanted)
      result.warnings.push_back("feature lines: the search grid's spacing was widened from " + std::to_string(wanted) +
        " to " + std::to_string(h) + " (at most " + std::to_string(options.maximumGridPoints) +
        " grid points): curves shorter or closer than that can be missed");
    result.spacing = h_ = h;
    origin_ = Vec3{ box.min.x - shift.x * h, box.min.y - shift.y * h, box.min.z - shift.z * h };
    nx_ = n[0], ny_ = n[1], nz_ = n[2];
    stride_[0] = 1, stride_[1] = nx_, stride_[2] = nx_ * ny_;
    precision_ = 1e-10 * diagonal_;
    probe_ = 1e-7 * diagonal_;
  }

  /// 1. Regions at the grid points.
  void classifyGridPoints()
  {
    region_.resize(static_cast<size_t>(nx_ * ny_ * nz_));
    for (std::int64_t k = 0; k < nz_; ++k)
    {
      for (std::int64_t j = 0; j < ny_; ++j)
        for (std::int64_t i = 0; i < nx_; ++i)
        {
          const std::int64_t id = index(i, j, k);
          region_[id] = oracle_.decide(pointAt(id));
        }
      report(0.4 * (k + 1) / nz_);
    }
  }

  /// 2. Grid faces of mixed cubes: walked along their edges, then bisected where a curve passes;
  /// in each cube, crossings of the same regions in pairs are linked, the others end at a junction.
  void findCrossings()
  {
    for (std::int64_t k = 0; k + 1 < nz_; ++k)
    {
      for (std::int64_t j = 0; j + 1 < ny_; ++j)
        for (std::int64_t i = 0; i + 1 < nx_; ++i)
          linkCube(index(i, j, k));
      report(0.4 + 0.5 * (k + 1) / nz_);
    }
    result_.gridFacesCrossed = crossings_.size();
  }

  /// Between two crossings joined in a cube the curve may bend (a corner of a box, a tight curve):
  /// the crossing on the plane halfway between them, where it lies off their chord, is inserted, and
  /// so on down to the tolerance; corners are then kept within a 256th of a grid step.
  void refineLinks()
  {
    tolerance_ = options_.tolerance > 0 ? options_.tolerance
      : options_.maxSegmentLength > 0   ? 0.05 * options_.maxSegmentLength
                                        : 0.01 * h_;
    std::vector<Link> refined;
    for (const Link& l : links_)
    {
      std::vector<int> path{ l.a };
      refine(l.a, l.b, 8, path);
      path.push_back(l.b);
      for (size_t k = 0; k + 1 < path.size(); ++k)
        refined.push_back({ path[k], path[k + 1] });
    }
    links_ = std::move(refined);
  }

  /// 3. The graph: crossings, then one junction vertex per group of touching cubes where curves end.
  void buildGraph()
  {
    crossingCount_ = static_cast<int>(crossings_.size());
    for (const Crossing& c : crossings_)
      nodes_.push_back(c.point);
    adjacent_.resize(nodes_.size());
    for (const Link& l : links_)
    {
      adjacent_[l.a].push_back(l.b);
      adjacent_[l.b].push_back(l.a);
    }
    for (const auto& [centre, ending] : mergeJunctionCubes())
      addJunction(centre, ending);
  }

  /// 4. Curves: chains between junctions and vertices that do not continue exactly one curve, then
  /// loops.
  std::vector<std::vector<int>> curves() const
  {
    std::set<std::pair<int, int>> walked;
    auto take = [&](int a, int b) { return walked.insert({ std::min(a, b), std::max(a, b) }).second; };
    std::vector<std::vector<int>> chains;
    auto walk = [&](int start, int next) {
      std::vector<int> chain{ start, next };
      // junctions end chains, so that a chain is one curve with one signature
      for (int previous = start, v = next; adjacent_[v].size() == 2 && v != start && v < crossingCount_;)
      {
        const int w = adjacent_[v][0] == previous ? adjacent_[v][1] : adjacent_[v][0];
        if (!take(v, w))
          break;
        chain.push_back(w);
        previous = v;
        v = w;
      }
      chains.push_back(std::move(chain));
    };
    for (int v = 0; v < static_cast<int>(nodes_.size()); ++v)
      if (adjacent_[v].size() != 2 || v >= crossingCount_)
        for (int w : adjacent_[v])
          if (take(v, w))
            walk(v, w);
    for (int v = 0; v < static_cast<int>(nodes_.size()); ++v)
      for (int w : adjacent_[v])
        if (take(v, w))
          walk(v, w);
    return chains;
  }

  /// 4a. A junction is placed inside its cube, from the curves' tangents; where curves meet at a
  /// small angle the last crossing of an arm can lie beyond it, and the arm would turn back there (a
  /// fold at 0 degrees). Such crossings are left out: the arm runs straight to the junction.
  void trimArms(std::vector<std::vector<int>>& chains) const
  {
    for (auto& chain : chains)
      for (int end = 0; end < 2; ++end)
      {
        while (chain.size() > 2 && chain.front() >= crossingCount_ &&
          angleAt(nodes_[chain[1]], nodes_[chain[0]], nodes_[chain[2]]) < 90.0)
          chain.erase(chain.begin() + 1);
        std::reverse(chain.begin(), chain.end());
      }
  }

  /// 4b. Curves between two junctions shorter than their chord length (curves crossing or touching
  /// at a small angle run within a grid step of each other for a while, and each cube along that
  /// stretch made a junction) collapse to one vertex: the mesh could not show them, and their ends
  /// would meet the other curves there at angles down to 0 degrees.
  void collapseShortCurves(std::vector<std::vector<int>>& chains)
  {
    SmallestRoot same(nodes_.size());
    std::vector<char> collapsed(chains.size(), 0);
    for (size_t c = 0; c < chains.size(); ++c)
    {
      const auto& chain = chains[c];
      if (chain.size() < 2 || chain.front() < crossingCount_ || chain.back() < crossingCount_)
        continue;
      double length = 0.0;
      for (size_t k = 0; k + 1 < chain.size(); ++k)
        length += norm(nodes_[chain[k + 1]] - nodes_[chain[k]]);
      // two junctions joined directly have no crossing between them to tell the materials
      // (crossings_ holds crossings only): the global chord length
      const int tag = tagOf(chain);
      const std::vector<int> materials = tag < crossingCount_ ? materialsOf(crossings_[tag].regions) : std::vector<int>{};
      if (!(length < lengthFor(materials)))
        continue;
      collapsed[c] = 1;
      same.join(chain.front(), chain.back());
    }
    std::map<int, std::vector<int>> members;
    for (int v = crossingCount_; v < static_cast<int>(nodes_.size()); ++v)
      members[same.root(v)].push_back(v);
    for (const auto& [root, group] : members)
      if (group.size() > 1)
      {
        Vec3 mean;
        for (int v : group)
          mean = mean + (1.0 / group.size()) * nodes_[v];
        nodes_[root] = mean;
      }
    std::vector<std::vector<int>> kept;
    for (size_t c = 0; c < chains.size(); ++c)
      if (!collapsed[c])
      {
        std::vector<int> chain = chains[c];
        chain.front() = same.root(chain.front());
        chain.back() = same.root(chain.back());
        kept.push_back(std::move(chain));
      }
    chains = std::move(kept);
  }

  /// 5. Each curve resampled on its own (its ends stay, being ends), then shared end vertices.
  void addCurves(const std::vector<std::vector<int>>& chains)
  {
    for (const auto& chain : chains)
      addCurve(chain);
  }

  /// 6. Creases of single inputs: each crease walked chord by chord, cut at the other inputs'
  /// crossings along it (exact for straight chords), each stretch probed beside its middle; runs of
  /// stretches seen with the same materials are the pieces. Ends where the crease passes into
  /// another input become vertices of the found curves there; the pieces are resampled as curves.
  void addCreases()
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

  void report(double fraction) const
  {
    if (options_.progress && !options_.progress(fraction))
      throw FeatureSearchAborted();
  }

private:
  std::int64_t index(std::int64_t i, std::int64_t j, std::int64_t k) const { return i + nx_ * (j + ny_ * k); }
  Vec3 pointAt(std::int64_t id) const
  {
    const std::int64_t i = id % nx_, j = (id / nx_) % ny_, k = id / (nx_ * ny_);
    return Vec3{ origin_.x + i * h_, origin_.y + j * h_, origin_.z + k * h_ };
  }

  const EdgeRegions& edge(std::int64_t p, int axis)
  {
    const std::int64_t key = 3 * p + axis;
    auto it = edges_.find(key);
    if (it == edges_.end())
      it = edges_.emplace(key, regionsAlong(oracle_, pointAt(p), pointAt(p + stride_[axis]))).first;
    return it->second;
  }

  /// The crossing on the grid face at lowest corner p normal to `axis`, or -1 (cached).
  int face(std::int64_t p, int axis)
  {
    const std::int64_t key = 3 * p + axis;
    if (auto it = faceCrossing_.find(key); it != faceCrossing_.end())
      return it->second;
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    Vec3 U, V;
    U[u] = h_;
    V[v] = h_;
    Rect q{ pointAt(p), U, V, edge(p, u), edge(p + stride_[v], u), edge(p, v), edge(p + stride_[u], v) };
    int found = -1;
    if (holdsCurve(loopOf(q)))
    {
      Crossing c = locate(oracle_, std::move(q), precision_);
      if (c.regions.size() >= 3 && isFeature(c.regions))
      {
        found = static_cast<int>(crossings_.size());
        crossings_.push_back(std::move(c));
      }
    }
    faceCrossing_.emplace(key, found);
    return found;
  }

  /// The cube at lowest corner p, when its corners are not all in one region.
  void linkCube(std::int64_t p)
  {
    bool mixed = false;
    for (int c = 1; c < 8 && !mixed; ++c)
      mixed = region_[p + (c & 1) * stride_[0] + ((c >> 1) & 1) * stride_[1] + ((c >> 2) & 1) * stride_[2]] != region_[p];
    if (!mixed)
      return;
    std::map<Signature, std::vector<int>> bySignature;
    for (int axis = 0; axis < 3; ++axis)
      for (std::int64_t side : { std::int64_t(0), stride_[axis] })
      {
        const int c = face(p + side, axis);
        if (c >= 0)
          bySignature[crossings_[c].regions].push_back(c);
      }
    std::vector<int> ending;
    for (const auto& [signature, ids] : bySignature)
    {
      if (ids.size() == 2)
        links_.push_back({ ids[0], ids[1] });
      else if (ids.size() == 4)
        pairPasses(ids);
      else
        ending.insert(ending.end(), ids.begin(), ids.end());
    }
    // one ending curve is kept too: its junction may be shared with a touching cube (mergeJunctionCubes)
    if (!ending.empty())
      junctionCubes_.push_back({ p, ending });
  }

  /// One curve passing a cube twice (a fold, two near-parallel pieces): two passes, paired by the
  /// shorter total chord, not a junction (that made zigzags meeting at 0 degrees).
  void pairPasses(const std::vector<int>& ids)
  {
    const auto d = [&](int a, int b) { return norm(crossings_[ids[a]].point - crossings_[ids[b]].point); };
    const double p01 = d(0, 1) + d(2, 3), p02 = d(0, 2) + d(1, 3), p03 = d(0, 3) + d(1, 2);
    const int partner = p01 <= p02 && p01 <= p03 ? 1 : p02 <= p03 ? 2 : 3;
    const int rest[2] = { partner == 1 ? 2 : 1, partner == 3 ? 2 : 3 };
    links_.push_back({ ids[0], ids[partner] });
    links_.push_back({ ids[rest[0]], ids[rest[1]] });
  }

  /// The curve with signature `regions` where it crosses the plane halfway between pa and pb, in the
  /// square of side |pb - pa| centred on their midpoint; false when it does not pass there.
  bool curveBetween(const Vec3& pa, const Vec3& pb, const Signature& regions, Crossing& m) const
  {
    const double L = norm(pb - pa);
    if (!(L > 4 * precision_))
      return false;
    return curveInSquare(0.5 * (pa + pb), pb - pa, L, regions, m);
  }

  /// The curve with signature `regions` where it crosses the plane through `centre` normal to
  /// `normal`, in the square of side L centred there; false when it does not pass there.
  bool curveInSquare(const Vec3& centre, const Vec3& normal, double L, const Signature& regions, Crossing& m) const
  {
    if (!(norm(normal) > 0))
      return false;
    const Vec3 n = (1.0 / norm(normal)) * normal;
    const int axis = std::abs(n.x) <= std::abs(n.y) && std::abs(n.x) <= std::abs(n.z) ? 0 : std::abs(n.y) <= std::abs(n.z) ? 1 : 2;
    Vec3 e;
    e[axis] = 1.0;
    Vec3 e1 = cross(n, e);
    e1 = (1.0 / norm(e1)) * e1;
    const Vec3 e2 = cross(n, e1);
    const Vec3 o = centre - (0.5 * L) * (e1 + e2);
    Rect q{ o, L * e1, L * e2, regionsAlong(oracle_, o, o + L * e1), regionsAlong(oracle_, o + L * e2, o + L * (e1 + e2)),
      regionsAlong(oracle_, o, o + L * e2), regionsAlong(oracle_, o + L * e1, o + L * (e1 + e2)) };
    if (!holdsCurve(loopOf(q)))
      return false;
    m = locate(oracle_, std::move(q), precision_);
    return m.regions == regions;
  }

  void refine(int a, int b, int depth, std::vector<int>& path)
  {
    const Vec3 pa = crossings_[a].point, pb = crossings_[b].point;
    Crossing m;
    if (depth == 0 || !curveBetween(pa, pb, crossings_[a].regions, m) || !(norm(m.point - 0.5 * (pa + pb)) > tolerance_))
      return;
    const int id = static_cast<int>(crossings_.size());
    crossings_.push_back(std::move(m));
    refine(a, id, depth - 1, path);
    path.push_back(id);
    refine(id, b, depth - 1, path);
  }

  /// Curves that meet near a face or corner of the grid end in neighbouring cubes (one arm in each):
  /// cubes where curves end and that touch (26 neighbours) are one junction, where two or more end.
  std::vector<Junction> mergeJunctionCubes() const
  {
    std::unordered_map<std::int64_t, int> cubeIndex;
    for (size_t c = 0; c < junctionCubes_.size(); ++c)
      cubeIndex.emplace(junctionCubes_[c].first, static_cast<int>(c));
    SmallestRoot touching(junctionCubes_.size());
    for (size_t c = 0; c < junctionCubes_.size(); ++c)
      for (int d = 0; d < 27; ++d)
      {
        const std::int64_t q = junctionCubes_[c].first + (d % 3 - 1) * stride_[0] + ((d / 3) % 3 - 1) * stride_[1] + (d / 9 - 1) * stride_[2];
        if (auto it = cubeIndex.find(q); it != cubeIndex.end())
          touching.join(static_cast<int>(c), it->second);
      }
    std::map<int, std::pair<std::vector<Vec3>, std::set<int>>> groups;
    for (size_t c = 0; c < junctionCubes_.size(); ++c)
    {
      auto& g = groups[touching.root(static_cast<int>(c))];
      g.first.push_back(pointAt(junctionCubes_[c].first) + Vec3{ 0.5 * h_, 0.5 * h_, 0.5 * h_ });
      g.second.insert(junctionCubes_[c].second.begin(), junctionCubes_[c].second.end());
    }
    std::vector<Junction> junctions;
    for (const auto& [unused, g] : groups)
      if (g.second.size() >= 2)
      {
        Junction j;
        for (const Vec3& c : g.first)
          j.centre = j.centre + (1.0 / g.first.size()) * c;
        j.ending.assign(g.second.begin(), g.second.end());
        junctions.push_back(std::move(j));
      }
    return junctions;
  }

  /// The chord length of a curve between these materials: the smallest listed, else the global one.
  double lengthFor(const std::vector<int>& materials) const
  {
    double length = options_.maxSegmentLength;
    for (int material : materials)
      if (auto it = options_.materialSegmentLength.find(material); it != options_.materialSegmentLength.end())
        length = length > 0 ? std::min(length, it->second) : it->second;
    return length;
  }

  /// The longest chord of a curve between these materials (a crease: `crease`), see
  /// FeatureLineOptions::materialChordLength; never below lengthFor.
  double chordLengthFor(const std::vector<int>& materials, bool crease) const
  {
    const double length = lengthFor(materials);
    if (length <= 0)
      return length;
    if (crease && options_.creaseChordLength > 0)
      return std::max(length, options_.creaseChordLength);
    double chord = HUGE_VAL;
    for (int material : materials)
      if (auto it = options_.materialChordLength.find(material); it != options_.materialChordLength.end())
        chord = std::min(chord, it->second);
    return std::isfinite(chord) ? std::max(length, chord) : length;
  }

  /// A crease seen with one set of materials; an end that enters another input is `entering`;
  /// `across[end]`: the materials the crease is seen with beyond that end (empty: none, not seen).
  struct CreasePiece
  {
    std::vector<Vec3> points;
    std::vector<int> materials;
    bool closed = false;
    bool entering[2] = { false, false };
    std::vector<int> across[2];
    int endPoint[2] = { -1, -1 };
  };

  /// Who is seen beside the crease at m (on chord ab): the input (domain `owner`) must decide the
  /// material on its side (probed along the inward bisector of the faces' normals, which way is
  /// inside asked of the input itself) and another material must lie across (the outward
  /// bisector). Empty: not seen, or three materials around it (a ring of probes): then it is a
  /// triple line the search finds (a tray's bottom edge on the cut plane over the bone).
  std::vector<int> seenAt(int owner, const Vec3& m, const Vec3& a, const Vec3& b, const std::array<Vec3, 2>& n) const
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

  void visiblePieces(int owner, const Crease& c, std::vector<CreasePiece>& pieces) const
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
  bool turnsAt(const FeatureLine& line, size_t k) const
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
  int meetingVertex(const Vec3& x, const std::vector<int>& meeting)
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
      const auto regions = signature_.find(bestLine);
      const double tolerance = toleranceFor(line.materials, lengthFor(line.materials));
      if (regions != signature_.end() && tolerance > 0)
        splitOnCurve(S.points[a], x, regions->second, tolerance, 8, inner);
      const size_t before = inner.size();
      inner.push_back(x);
      if (regions != signature_.end() && tolerance > 0)
        splitOnCurve(x, S.points[b], regions->second, tolerance, 8, inner);
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
  int endVertex(const Vec3& x, double reach)
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

  static std::array<double, 3> key(const Vec3& p) { return { p.x, p.y, p.z }; }

  void addCreasePiece(const CreasePiece& p)
  {
    FeatureLine line;
    line.materials = p.materials;
    line.triple = line.materials.size() >= 3;
    line.crease = true;
    const size_t m = p.closed ? p.points.size() - 1 : p.points.size();
    addResampledCurve(std::move(line), std::vector<Vec3>(p.points.begin(), p.points.begin() + static_cast<long>(m)),
      p.closed, [&](int end) { return p.endPoint[end]; });
  }

  /// Resamples the curve through `points` (closed: back to the first, which is not repeated)
  /// for its materials and adds it as `line`; an open curve's ends are the result's points
  /// endPoint(0) and endPoint(1), asked for when reached (first end, inner points, last end).
  /// `regions`: the signature of a curve found (none for a crease, whose points are the input's own).
  template <typename EndPoint>
  void addResampledCurve(FeatureLine line, std::vector<Vec3> points, bool closed, EndPoint endPoint, const Signature* regions = nullptr)
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
      along = onCurve(along, *regions, toleranceFor(line.materials, lengthFor(line.materials)));
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

  /// The chain `along` with the curve's own points inserted where a chord's midpoint lies farther
  /// than `tolerance` from the curve (the crossing in the plane halfway, as refine does), down to
  /// chords within it: resampling kept the chords near the found points only, and a chord off its
  /// interfaces by more than their facets' tolerance leaves the mesher a gap between the segment
  /// and the surfaces through the curve, which it filled with ever smaller cells (issue 13: random_05
  /// at radius-edge 1.1, chords 0.03-0.1 off a triple line at a grazing angle).
  /// Appends to `out` the curve's points between a and b (both on it, neither appended) where the
  /// chord's midpoint lies farther than `tolerance` from the curve, recursively (`depth` levels).
  void splitOnCurve(const Vec3& a, const Vec3& b, const Signature& regions, double tolerance, int depth, std::vector<Vec3>& out) const
  {
    Crossing m;
    if (depth > 0 && curveBetween(a, b, regions, m) && norm(m.point - 0.5 * (a + b)) > tolerance)
    {
      splitOnCurve(a, m.point, regions, tolerance, depth - 1, out);
      out.push_back(m.point);
      splitOnCurve(m.point, b, regions, tolerance, depth - 1, out);
    }
  }

  std::vector<Vec3> onCurve(const std::vector<Vec3>& along, const Signature& regions, double tolerance) const
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
  /// kept corners to a 256th of a grid step, which leaves chords beside the interfaces next to
  /// them; with these vertices and the midpoint splits the 1.1 study ended random_04 and random_05
  /// (the splits alone ran random_04 into the vertex budget). Every bend as a vertex cut a bone
  /// rim on a voxel staircase at each cell plane (0.3-0.8 mm chords where its tolerance is 0.2),
  /// and the mesh graded down to those chords (issue 13).
  std::vector<Vec3> withBends(const std::vector<Vec3>& along, const Signature& regions, double tolerance) const
  {
    std::vector<Vec3> out{ along.front() };
    std::vector<BendPlane> planes;
    for (size_t k = 0; k + 1 < along.size(); ++k)
    {
      const Vec3 a = out.back();
      Vec3 b = along[k + 1];
      const double L = norm(b - a);
      planes.clear();
      if (L > 4 * precision_)
        for (const auto& d : oracle_.domains())
          d->bendPlanes(a, b, planes);
      std::vector<std::pair<double, Vec3>> bends; // (distance from a, point on the curve)
      for (const BendPlane& plane : planes)
      {
        Crossing m;
        if (curveInPlane(plane, L, regions, m))
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

  /// Of the points `inner` (in order from a to b), those a polyline from a to b needs so that every
  /// one of them lies within `tolerance` of it: the farthest from the chord first, recursively
  /// (Douglas-Peucker).
  static std::vector<Vec3> bendsBeyond(const Vec3& a, const Vec3& b, const std::vector<Vec3>& inner, double tolerance)
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

  /// The curve with signature `regions` where it crosses `plane`, in the square of side L centred
  /// on plane.point; false when it does not pass there.
  bool curveInPlane(const BendPlane& plane, double L, const Signature& regions, Crossing& m) const
  {
    return curveInSquare(plane.point, plane.normal, L, regions, m);
  }

  /// The chord tolerance of a curve between these materials: the smallest of their own
  /// (options.materialTolerance), the global one for materials without.
  double toleranceFor(const std::vector<int>& materials, double length) const
  {
    const double global = options_.tolerance > 0 ? options_.tolerance : 0.05 * length;
    double tolerance = HUGE_VAL;
    for (int material : materials)
      if (material >= 0)
      {
        auto it = options_.materialTolerance.find(material);
        tolerance = std::min(tolerance, it != options_.materialTolerance.end() ? it->second : global);
      }
    return std::isfinite(tolerance) ? tolerance : global;
  }

  /// The crossing that tells a chain's regions: its first vertex, unless that is a junction.
  int tagOf(const std::vector<int>& chain) const { return chain[chain[0] < crossingCount_ ? 0 : 1]; }

  /// A junction vertex for the curves `ending` near `centre`: the meeting point of their tangents
  /// (exact for straight curves), else their mean.
  void addJunction(const Vec3& centre, const std::vector<int>& ending)
  {
    std::vector<Vec3> at, along;
    Vec3 mean;
    for (int c : ending)
    {
      mean = mean + (1.0 / ending.size()) * nodes_[c];
      if (adjacent_[c].size() == 1 && adjacent_[c][0] < crossingCount_)
      {
        const Vec3 d = nodes_[c] - nodes_[adjacent_[c][0]];
        if (norm(d) > 0)
        {
          at.push_back(nodes_[c]);
          along.push_back((1.0 / norm(d)) * d);
        }
      }
    }
    Vec3 x;
    if (at.size() < 2 || !nearestToLines(at, along, x) || norm(x - centre) > 1.5 * h_)
      x = mean;
    const int junction = static_cast<int>(nodes_.size());
    nodes_.push_back(x);
    adjacent_.emplace_back();
    for (int c : ending)
    {
      adjacent_[c].push_back(junction);
      adjacent_[junction].push_back(c);
    }
  }

  /// The result's point of graph node `node`, shared by the curves that end there.
  int pointOfNode(int node)
  {
    auto [it, added] = sharedPoint_.emplace(node, static_cast<int>(result_.segments.points.size()));
    if (added)
      result_.segments.points.push_back(nodes_[node]);
    return it->second;
  }

  void addCurve(const std::vector<int>& chain)
  {
    if (chain.size() < 2)
      return;
    const int tagged = tagOf(chain);
    if (tagged >= crossingCount_)
      return; // two junctions joined directly: no crossing tells the regions (does not happen)
    FeatureLine line;
    line.materials = materialsOf(crossings_[tagged].regions);
    line.triple = line.materials.size() >= 3;
    // A loop through a junction stays open there, so the junction is kept as its two ends.
    const bool closed = chain.back() == chain.front() && adjacent_[chain.front()].size() == 2 && chain.front() < crossingCount_;
    const size_t m = closed ? chain.size() - 1 : chain.size();
    if (closed && m < 3)
      return;
    std::vector<Vec3> points;
    for (size_t k = 0; k < m; ++k)
      points.push_back(nodes_[chain[k]]);
    const Signature regions = crossings_[tagged].regions;
    addResampledCurve(std::move(line), std::move(points), closed,
      [&](int end) { return pointOfNode(end == 0 ? chain.front() : chain.back()); }, &regions);
  }

  /// At the chord length of the curve's materials (chordLengthFor; no segment length: left as found), within
  /// the smallest of their chord tolerances of the curve: of the found points, less what the curve
  /// bulges between them (at most three quarters of the tolerance is given up to that).
  void resampleCurve(FeatureSegments& piece, const std::vector<int>& materials, bool crease) const
  {
    const double length = lengthFor(materials);
    if (length <= 0)
      return;
    const double tolerance = toleranceFor(materials, length);
    resampleFeatureLines(
      piece, chordLengthFor(materials, crease), std::max(tolerance - bulgeBetweenSamples(piece, options_.smallAngle), 0.25 * tolerance), options_.smallAngle);
  }

  const HierarchicalOracle& oracle_;
  const FeatureLineOptions& options_;
  FeatureLines& result_;
  double diagonal_ = 0, h_ = 0, precision_ = 0, tolerance_ = 0;
  Vec3 origin_;
  std::int64_t nx_ = 0, ny_ = 0, nz_ = 0;
  std::int64_t stride_[3] = { 0, 0, 0 };
  std::vector<Region> region_;
  std::unordered_map<std::int64_t, EdgeRegions> edges_;
  std::vector<Crossing> crossings_;
  std::unordered_map<std::int64_t, int> faceCrossing_; // 3 * lowest corner + normal axis -> crossing or -1
  std::vector<Link> links_;
  std::vector<std::pair<std::int64_t, std::vector<int>>> junctionCubes_; // cube, curves ending in it
  int crossingCount_ = 0;
  std::vector<Vec3> nodes_;
  std::vector<std::vector<int>> adjacent_;
  std::map<int, int> sharedPoint_; // node -> point of result.segments
  std::map<std::array<double, 3>, int> creasePoint_; // crease ends -> point of result.segments
  std::map<int, Signature> signature_;               // curve found (index in result.lines) -> its regions
  /// How far (grid steps) a curve found may run from a crease's point where its materials change:
  /// a V of two arms closer than a step is cut about a step over the angle between them short of
  /// its tip (8: arms down to about 7 degrees apart; below 60 the mesher is warned anyway).
  static constexpr double kMeetingReach = 8.0;
  double probe_ = 0;                                  // how far beside a crease its sides are probed
};

}

std::vector<SmallFeatureAngle> findSmallFeatureAngles(const FeatureSegments& f, double below, std::vector<std::string>& warnings)
{
  std::vector<SmallFeatureAngle> found;
  const auto& P = f.points;
  std::vector<std::vector<int>> neighbours(P.size());
  for (const auto& s : f.segments)
  {
    neighbours[s[0]].push_back(s[1]);
    neighbours[s[1]].push_back(s[0]);
  }
  for (size_t v = 0; v < P.size(); ++v)
  {
    double smallest = 180.0;
    for (size_t a = 0; a < neighbours[v].size(); ++a)
      for (size_t b = a + 1; b < neighbours[v].size(); ++b)
        smallest = std::min(smallest, angleAt(P[v], P[neighbours[v][a]], P[neighbours[v][b]]));
    if (smallest < below)
    {
      found.push_back({ static_cast<int>(v), smallest });
      if (found.size() > 5)
        continue; // the first five named, the rest counted below
      std::ostringstream o;
      o.precision(3);
      o << "feature lines meet at " << smallest << " degrees at " << describe(P[v]) << " (below " << below
        << ": refinement may not end there; the vertex budget bounds it)";
      warnings.push_back(o.str());
    }
  }
  if (found.size() > 5)
  {
    double smallest = 180.0;
    for (const auto& a : found)
      smallest = std::min(smallest, a.degrees);
    std::ostringstream o;
    o.precision(3);
    o << "feature lines meet below " << below << " degrees at " << found.size() - 5
      << " more vertices (smallest angle of all " << smallest << " degrees)";
    warnings.push_back(o.str());
  }
  return found;
}

void checkCreaseAngle(double angle, const char* what)
{
  if (angle > 0.0 && angle <= 180.0)
    return;
  std::ostringstream o;
  o << what << " " << angle << " is out of range (above 0 to 180 degrees; 180 = no creases)";
  throw InputError(o.str());
}

FeatureLines findFeatureLines(const HierarchicalOracle& oracle, const FeatureLineOptions& options)
{
  checkCreaseAngle(options.creaseAngle, "feature lines: creaseAngle");
  FeatureLines result;
  FeatureLineSearch search(oracle, options, result);
  search.classifyGridPoints();
  search.findCrossings();
  search.refineLinks();
  search.buildGraph();
  std::vector<std::vector<int>> chains = search.curves();
  search.trimArms(chains);
  search.collapseShortCurves(chains);
  search.addCurves(chains);
  search.addCreases();
  // 6. Small angles: between curves at a shared vertex, and where one curve turns sharply.
  result.smallAngles = findSmallFeatureAngles(result.segments, options.smallAngle, result.warnings);
  search.report(1.0);
  return result;
}
}
