// SPDX-License-Identifier: GPL-3.0-or-later
#include "MeshQuality.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <unordered_map>
#include <unordered_set>

namespace omesh
{
double signedVolume(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d)
{
  return dot(cross(b - a, c - a), d - a) / 6.0;
}

double smallestAltitude(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d)
{
  const double twiceArea = std::max({ norm(cross(b - a, c - a)), norm(cross(b - a, d - a)), norm(cross(c - a, d - a)),
    norm(cross(c - b, d - b)) });
  return twiceArea > 0 ? 6.0 * std::abs(signedVolume(a, b, c, d)) / twiceArea : 0.0;
}

namespace
{
/// Outward normal of face f of tetrahedron p (opposite vertex f), not normalised: the same
/// values for minDihedralAngle and dihedralAnglesCertainlyAtLeast.
inline Vec3 outwardFaceNormal(const Vec3 p[4], int f)
{
  const Vec3& u = p[(f + 1) % 4];
  const Vec3& v = p[(f + 2) % 4];
  const Vec3& w = p[(f + 3) % 4];
  const Vec3 m = cross(v - u, w - u);
  return dot(m, p[f] - u) > 0 ? -1.0 * m : m;
}
}

namespace
{
/// The cosines of the six dihedral angles of abcd (pi minus the angle between the outward normals
/// of the two faces at an edge); false for a tetrahedron with a degenerate face. `twiceAreas`, if
/// given, gets the four faces' doubled areas (face f opposite corner f).
bool dihedralCosines(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, double cosines[6],
  double* twiceAreas = nullptr)
{
  const Vec3 p[4] = { a, b, c, d };
  Vec3 n[4];
  for (int f = 0; f < 4; ++f)
  {
    const Vec3 m = outwardFaceNormal(p, f);
    const double l = norm(m);
    if (twiceAreas)
      twiceAreas[f] = l;
    if (!(l > 0))
      return false;
    n[f] = (1.0 / l) * m;
  }
  int k = 0;
  for (int i = 0; i < 4; ++i)
    for (int j = i + 1; j < 4; ++j)
      cosines[k++] = std::clamp(-dot(n[i], n[j]), -1.0, 1.0);
  return true;
}
}

double largestDihedralCosine(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d)
{
  double cosines[6];
  if (!dihedralCosines(a, b, c, d, cosines))
    return 1.0;
  return *std::max_element(cosines, cosines + 6);
}

double minDihedralAngle(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d)
{
  // the smallest angle has the largest cosine: one acos instead of six (acos is monotonic, so the
  // result is the same to the bit); acos(1) = 0 for a flat one
  return std::acos(largestDihedralCosine(a, b, c, d)) * 180.0 / M_PI;
}

double maxDihedralAngle(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d)
{
  double cosines[6];
  if (!dihedralCosines(a, b, c, d, cosines))
    return 180.0;
  return std::acos(*std::min_element(cosines, cosines + 6)) * 180.0 / M_PI;
}

bool dihedralAngleRange(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, double& smallest, double& largest)
{
  double cosines[6];
  if (!dihedralCosines(a, b, c, d, cosines))
    return false;
  const auto [lo, hi] = std::minmax_element(cosines, cosines + 6);
  smallest = std::acos(*hi) * 180.0 / M_PI;
  largest = std::acos(*lo) * 180.0 / M_PI;
  return true;
}

TetShape tetShape(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d)
{
  return tetShape(a, b, c, d, std::abs(signedVolume(a, b, c, d)));
}

void edgeLengths(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, double l[6])
{
  const Vec3 p[4] = { a, b, c, d };
  for (int i = 0, e = 0; i < 4; ++i)
    for (int j = i + 1; j < 4; ++j, ++e)
      l[e] = norm(p[j] - p[i]);
}

namespace
{
/// Circumradius from the products of opposite edges' lengths (a tetrahedron's Heron) and the
/// volume; infinite for a flat tetrahedron. No circumcentre (a solve) is needed.
double circumradiusOf(const double l[6], double volume)
{
  if (!(volume > 0))
    return std::numeric_limits<double>::infinity();
  const double x = l[0] * l[5], y = l[1] * l[4], z = l[2] * l[3];
  const double product = std::max(0.0, (x + y + z) * (x + y - z) * (x - y + z) * (-x + y + z));
  return std::sqrt(product) / (24.0 * volume);
}
}

TetShape tetShape(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, double volume)
{
  double l[6];
  edgeLengths(a, b, c, d, l);
  return tetShape(a, b, c, d, volume, l);
}

TetShape tetShape(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, double volume, const double l[6])
{
  TetShape s;
  double cosines[6], twiceAreas[4] = { 0, 0, 0, 0 };
  if (dihedralCosines(a, b, c, d, cosines, twiceAreas))
  {
    // the same operations as minDihedralAngle and maxDihedralAngle: the same values to the bit
    const auto [lo, hi] = std::minmax_element(cosines, cosines + 6);
    s.minDihedral = std::acos(*hi) * 180.0 / M_PI;
    s.maxDihedral = std::acos(*lo) * 180.0 / M_PI;
  }
  const double squares = l[0] * l[0] + l[1] * l[1] + l[2] * l[2] + l[3] * l[3] + l[4] * l[4] + l[5] * l[5];
  const double shortest = *std::min_element(l, l + 6), longest = *std::max_element(l, l + 6);
  s.volume = volume;
  s.longestEdge = longest;
  s.edgeRatio = longest > 0 ? shortest / longest : 0.0;
  const double circumradius = circumradiusOf(l, volume);
  s.radiusEdge = circumradius / shortest; // as radiusEdgeRatio
  if (volume > 0)
  {
    const double inradius = 3.0 * volume / (0.5 * (twiceAreas[0] + twiceAreas[1] + twiceAreas[2] + twiceAreas[3]));
    const double ratio = 3.0 * inradius / circumradius;
    s.radiusRatio = std::isfinite(ratio) ? ratio : 0.0;
    const double root = std::cbrt(3.0 * volume); // (3 |V|)^(2/3), without pow's cost
    s.meanRatio = 12.0 * root * root / squares;
  }
  return s;
}

bool dihedralAnglesCertainlyAtLeast(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, double cosBound)
{
  // An angle is below the bound where the cosine between two outward normals, -m_i.m_j / (|m_i|
  // |m_j|), is above cosBound; certainly not where -m_i.m_j <= 0 or (m_i.m_j)^2 < k^2 |m_i|^2 |m_j|^2
  // with k = cosBound - 1e-9 (relative rounding here and in minDihedralAngle: a few 1e-16).
  // Strict comparisons: a flat face, an underflow or a NaN gives false.
  const double k = cosBound - 1e-9;
  if (!(k > 0.0))
    return false;
  const Vec3 p[4] = { a, b, c, d };
  Vec3 m[4];
  double sq[4];
  for (int f = 0; f < 4; ++f)
  {
    m[f] = outwardFaceNormal(p, f);
    sq[f] = dot(m[f], m[f]);
    if (!(sq[f] > 0.0))
      return false;
  }
  const double k2 = k * k;
  for (int i = 0; i < 4; ++i)
    for (int j = i + 1; j < 4; ++j)
    {
      const double mm = dot(m[i], m[j]);
      if (!(mm >= 0.0 || mm * mm < k2 * (sq[i] * sq[j])))
        return false;
    }
  return true;
}

Vec3 circumcenter(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d)
{
  const Vec3 u = b - a, v = c - a, w = d - a;
  const double det = 2.0 * dot(u, cross(v, w));
  if (det == 0.0)
    return { std::nan(""), std::nan(""), std::nan("") };
  const Vec3 num = dot(u, u) * cross(v, w) + dot(v, v) * cross(w, u) + dot(w, w) * cross(u, v);
  return a + (1.0 / det) * num;
}

double radiusEdgeRatio(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d)
{
  double l[6];
  edgeLengths(a, b, c, d, l);
  return circumradiusOf(l, std::abs(signedVolume(a, b, c, d))) / *std::min_element(l, l + 6);
}

std::map<int, double> materialVolumes(const TetMesh& mesh)
{
  std::map<int, double> v;
  for (size_t t = 0; t < mesh.tets.size(); ++t)
  {
    const auto& k = mesh.tets[t];
    v[mesh.tetMaterial[t]] += std::abs(signedVolume(mesh.points[k[0]], mesh.points[k[1]], mesh.points[k[2]], mesh.points[k[3]]));
  }
  return v;
}

namespace
{
uint64_t edgeKey(int a, int b)
{
  const uint64_t lo = static_cast<uint64_t>(std::min(a, b)), hi = static_cast<uint64_t>(std::max(a, b));
  return (lo << 32) | hi;
}

/// The vertices that tetrahedra use, hashed on a grid of spacing h.
class UsedVertexGrid
{
public:
  UsedVertexGrid(const TetMesh& mesh, const std::vector<char>& used, double h)
    : mesh_(mesh)
    , h_(h)
  {
    for (size_t i = 0; i < mesh.points.size(); ++i)
      if (used[i])
        grid_[key(mesh.points[i])].push_back(static_cast<int>(i));
  }

  /// The vertices within `tol` of segment ab of length `len`: (parameter along ab clamped to
  /// [0, len], vertex), sorted.
  std::vector<std::pair<double, int>> onSegment(const Vec3& a, const Vec3& b, double len, double tol) const
  {
    const Vec3 d = (1.0 / len) * (b - a);
    std::vector<std::pair<double, int>> on;
    std::unordered_set<int> seen;
    const int steps = static_cast<int>(std::ceil(len / h_)) + 1;
    for (int k = 0; k <= steps; ++k)
    {
      const Vec3 c = lerp(a, b, std::min(1.0, double(k) / steps));
      for (int dx = -1; dx <= 1; ++dx)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dz = -1; dz <= 1; ++dz)
          {
            auto it = grid_.find(key(c + Vec3{ dx * h_, dy * h_, dz * h_ }));
            if (it == grid_.end())
              continue;
            for (int v : it->second)
            {
              if (!seen.insert(v).second)
                continue;
              const Vec3 w = mesh_.points[v] - a;
              const double t = dot(w, d);
              if (t >= -tol && t <= len + tol && norm(w - t * d) <= tol)
                on.emplace_back(std::clamp(t, 0.0, len), v);
            }
          }
    }
    std::sort(on.begin(), on.end());
    return on;
  }

private:
  uint64_t key(const Vec3& p) const
  {
    const auto q = [this](double x) { return static_cast<uint64_t>(static_cast<int64_t>(std::floor(x / h_)) & 0x1fffff); };
    return (q(p.x) << 42) | (q(p.y) << 21) | q(p.z);
  }

  const TetMesh& mesh_;
  const double h_;
  std::unordered_map<uint64_t, std::vector<int>> grid_;
};

/// Marks present the pieces a mesh edge covers by passing straight through input points that are
/// no mesh vertices: CGAL's protecting balls join consecutive ball centres, and where the line runs
/// straight through a point of degree 2 (a found curve's crossing of a label map's cell plane) that
/// edge is the line itself. From each piece with one end a vertex u and the other an input point q,
/// the walk crosses q into the next segment (whole segments without a vertex included, up to
/// kMaxSkipped points) to the first vertex w; the pieces walked are present when u and w are joined
/// by an edge and every point crossed lies within `tolerance` x |uw| of it.
void coverStraightThroughPoints(const TetMesh& mesh, const FeatureSegments& features, double tolerance,
  const std::unordered_set<uint64_t>& edges, const std::vector<std::pair<size_t, size_t>>& piecesOf,
  std::vector<TetMesh::Segment>& pieces)
{
  constexpr int kMaxSkipped = 64;
  const std::vector<std::vector<size_t>> inc = features.incidence();
  // The piece of segment s at its end point q (its first piece when q is the segment's start).
  auto pieceAt = [&](size_t s, int q) {
    return features.segments[s][0] == q ? piecesOf[s].first : piecesOf[s].first + piecesOf[s].second - 1;
  };
  for (size_t s = 0; s < features.segments.size(); ++s)
    for (int end = 0; end < 2; ++end)
    {
      const int startQ = features.segments[s][end];
      const size_t first = pieceAt(s, startQ);
      if (pieces[first].present)
        continue;
      const int u = end == 0 ? pieces[first].bId : pieces[first].aId; // the far end of the piece
      if (u < 0 || (end == 0 ? pieces[first].aId : pieces[first].bId) >= 0)
        continue;
      std::vector<size_t> walked{ first };
      std::vector<int> crossed;
      int q = startQ;
      size_t seg = s;
      int w = -1;
      while (w < 0 && static_cast<int>(crossed.size()) < kMaxSkipped && inc[q].size() == 2)
      {
        crossed.push_back(q);
        seg = inc[q][0] == seg ? inc[q][1] : inc[q][0];
        const size_t next = pieceAt(seg, q);
        walked.push_back(next);
        const bool forward = features.segments[seg][0] == q;
        w = forward ? pieces[next].bId : pieces[next].aId;
        if (w < 0) // a whole segment without a vertex: on to its far end
          q = features.segments[seg][forward ? 1 : 0];
        if (seg == s)
          break; // a closed loop without a vertex
      }
      if (w < 0 || w == u || !edges.count(edgeKey(u, w)))
        continue;
      const Vec3 a = mesh.points[u], b = mesh.points[w];
      const double len = norm(b - a);
      const bool onEdge = std::all_of(crossed.begin(), crossed.end(), [&](int c) {
        const Vec3 x = features.points[c] - a;
        const double t = dot(x, b - a) / (len * len);
        return t > 0 && t < 1 && norm(x - t * (b - a)) <= tolerance * len;
      });
      if (onEdge)
        for (size_t k : walked)
          pieces[k].present = true;
    }
}
}

std::vector<TetMesh::Segment> locateFeatureSegments(
  const TetMesh& mesh, const FeatureSegments& features, double tolerance)
{
  std::vector<TetMesh::Segment> pieces;
  if (features.empty())
    return pieces;
  std::vector<char> used(mesh.points.size(), 0);
  for (const auto& t : mesh.tets)
    for (int v : t)
      used[v] = 1;
  // Hash the vertices of tetrahedra on a grid of the mean segment length.
  double total = 0.0;
  for (size_t s = 0; s < features.segments.size(); ++s)
    total += features.length(s);
  const UsedVertexGrid grid(mesh, used, std::max(total / features.segments.size(), 1e-12));
  // The mesh vertices on each segment; only edges between such vertices are ever asked for, so
  // only those are hashed (not the mesh's every edge).
  std::vector<std::vector<std::pair<double, int>>> onSegment(features.segments.size());
  std::vector<char> onLine(mesh.points.size(), 0);
  for (size_t s = 0; s < features.segments.size(); ++s)
  {
    const Vec3 a = features.points[features.segments[s][0]], b = features.points[features.segments[s][1]];
    const double len = features.length(s);
    onSegment[s] = grid.onSegment(a, b, len, tolerance * len);
    for (const auto& station : onSegment[s])
      onLine[station.second] = 1;
  }
  std::unordered_set<uint64_t> edges;
  for (const auto& t : mesh.tets)
    for (int i = 0; i < 4; ++i)
      if (onLine[t[i]])
        for (int j = i + 1; j < 4; ++j)
          if (onLine[t[j]])
            edges.insert(edgeKey(t[i], t[j]));

  std::vector<std::pair<size_t, size_t>> piecesOf(features.segments.size()); // first piece, count
  for (size_t s = 0; s < features.segments.size(); ++s)
  {
    piecesOf[s].first = pieces.size();
    const Vec3 a = features.points[features.segments[s][0]], b = features.points[features.segments[s][1]];
    const double len = features.length(s), tol = tolerance * len;
    const std::vector<std::pair<double, int>>& on = onSegment[s];
    // Pieces between consecutive stations: the segment's ends (mesh vertices or not) and the
    // mesh vertices on it.
    std::vector<std::pair<double, int>> stations;
    if (on.empty() || on.front().first > tol)
      stations.emplace_back(0.0, -1);
    stations.insert(stations.end(), on.begin(), on.end());
    if (on.empty() || on.back().first < len - tol)
      stations.emplace_back(len, -1);
    for (size_t i = 0; i + 1 < stations.size(); ++i)
    {
      TetMesh::Segment piece;
      piece.a = stations[i].second >= 0 ? mesh.points[stations[i].second] : lerp(a, b, stations[i].first / len);
      piece.b = stations[i + 1].second >= 0 ? mesh.points[stations[i + 1].second] : lerp(a, b, stations[i + 1].first / len);
      piece.aId = stations[i].second;
      piece.bId = stations[i + 1].second;
      piece.input = static_cast<int>(s);
      if (piece.aId >= 0 && piece.bId >= 0)
        piece.present = edges.count(edgeKey(piece.aId, piece.bId)) > 0;
      pieces.push_back(piece);
    }
    piecesOf[s].second = pieces.size() - piecesOf[s].first;
  }
  coverStraightThroughPoints(mesh, features, tolerance, edges, piecesOf, pieces);
  return pieces;
}

double featureCoverage(const std::vector<TetMesh::Segment>& pieces, const FeatureSegments& features)
{
  double total = 0.0, covered = 0.0;
  for (size_t s = 0; s < features.segments.size(); ++s)
    total += features.length(s);
  for (const auto& p : pieces)
    if (p.present)
      covered += norm(p.b - p.a);
  return total > 0 ? std::min(1.0, covered / total) : 1.0;
}
}
