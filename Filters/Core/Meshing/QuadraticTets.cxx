// SPDX-License-Identifier: GPL-3.0-or-later
#include "QuadraticTets.h"

#include "FieldDataKeys.h"
#include "HierarchicalOracle.h"
#include "MeshQuality.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>

namespace omesh
{
namespace
{
/// Gradient of the position with respect to barycentric coordinate k at l: (4 l_k - 1) x_k plus
/// 4 l_j x_kj over the edges kj at corner k.
Vec3 positionGradient(const std::array<Vec3, 10>& x, const std::array<double, 4>& l, int k)
{
  Vec3 g = (4.0 * l[k] - 1.0) * x[k];
  for (int e = 0; e < 6; ++e)
  {
    const int i = kQuadraticTetEdges[e][0], j = kQuadraticTetEdges[e][1];
    if (i == k)
      g = g + (4.0 * l[j]) * x[4 + e];
    else if (j == k)
      g = g + (4.0 * l[i]) * x[4 + e];
  }
  return g;
}

// The sample of the validity check: the 10 nodes and the 4 Gauss points of the degree-2 rule.
constexpr double kGaussA = 0.5854101966249685, kGaussB = 0.1381966011250105;
const std::array<std::array<double, 4>, 14> kSample = { {
  { 1, 0, 0, 0 }, { 0, 1, 0, 0 }, { 0, 0, 1, 0 }, { 0, 0, 0, 1 },
  { 0.5, 0.5, 0, 0 }, { 0, 0.5, 0.5, 0 }, { 0.5, 0, 0.5, 0 }, { 0.5, 0, 0, 0.5 }, { 0, 0.5, 0, 0.5 }, { 0, 0, 0.5, 0.5 },
  { kGaussA, kGaussB, kGaussB, kGaussB }, { kGaussB, kGaussA, kGaussB, kGaussB }, { kGaussB, kGaussB, kGaussA, kGaussB },
  { kGaussB, kGaussB, kGaussB, kGaussA },
} };

std::uint64_t edgeKey(int a, int b)
{
  if (a > b)
    std::swap(a, b);
  return (static_cast<std::uint64_t>(a) << 32) | static_cast<std::uint32_t>(b);
}

/// What the interface faces around one edge say about it.
struct EdgeInterface
{
  int faces = 0;          ///< interface faces at the edge
  int lo = 0, hi = 0;     ///< their material pair (lo < hi, kOutside = -1 for the exterior)
  bool samePair = true;   ///< every face has the pair lo/hi
  Vec3 normalSum;         ///< sum of the faces' unit normals, pointing from lo to hi
};
}

double quadraticTetJacobian(const std::array<Vec3, 10>& x, const std::array<double, 4>& l)
{
  const Vec3 g0 = positionGradient(x, l, 0);
  return dot(positionGradient(x, l, 1) - g0, cross(positionGradient(x, l, 2) - g0, positionGradient(x, l, 3) - g0));
}

double quadraticTetJacobianRatio(const std::array<Vec3, 10>& x)
{
  const double straight = 6.0 * signedVolume(x[0], x[1], x[2], x[3]);
  if (!(std::abs(straight) > 0.0))
    return -std::numeric_limits<double>::infinity();
  double smallest = std::numeric_limits<double>::infinity();
  for (const auto& l : kSample)
    smallest = std::min(smallest, quadraticTetJacobian(x, l) / straight);
  return smallest;
}

double quadraticTetVolume(const std::array<Vec3, 10>& x)
{
  // Keast's 5-point rule, exact for the cubic det J (weights of the unit tetrahedron, volume 1/6).
  constexpr double a = 0.5, b = 1.0 / 6.0;
  const std::array<std::array<double, 4>, 4> outer = { { { a, b, b, b }, { b, a, b, b }, { b, b, a, b }, { b, b, b, a } } };
  double sum = -0.8 * quadraticTetJacobian(x, { 0.25, 0.25, 0.25, 0.25 });
  for (const auto& l : outer)
    sum += 0.45 * quadraticTetJacobian(x, l);
  return sum / 6.0;
}

namespace
{
/// makeQuadraticTets step by step: the linear mesh's edges (sorted keys, so node ids do not depend
/// on the tetrahedra's order), what the interface faces say about each, the mid-edge nodes snapped
/// onto the oracle's interfaces, then pulled back where a tetrahedron's Jacobian gets too small.
class QuadraticTetBuilder
{
public:
  QuadraticTetBuilder(const TetMesh& mesh, const QuadraticOptions& options)
    : mesh_(mesh)
    , options_(options)
    , nCorners_(mesh.points.size())
    , nTets_(mesh.tets.size())
    , corners_(mesh.tets)
  {
    for (auto& k : corners_)
      if (signedVolume(mesh.points[k[0]], mesh.points[k[1]], mesh.points[k[2]], mesh.points[k[3]]) < 0)
        std::swap(k[0], k[1]);
    edgeKeys_.reserve(6 * nTets_);
    for (const auto& k : corners_)
      for (const auto& e : kQuadraticTetEdges)
        edgeKeys_.push_back(edgeKey(k[e[0]], k[e[1]]));
    std::sort(edgeKeys_.begin(), edgeKeys_.end());
    edgeKeys_.erase(std::unique(edgeKeys_.begin(), edgeKeys_.end()), edgeKeys_.end());
    nEdges_ = edgeKeys_.size();
  }

  /// Interface faces (between two materials, or a material and the outside) and their edges.
  void findInterfaceEdges()
  {
    std::vector<std::pair<std::array<int, 3>, std::size_t>> faces; // sorted corner ids, 4 tet + face
    faces.reserve(4 * nTets_);
    for (std::size_t t = 0; t < nTets_; ++t)
      for (int f = 0; f < 4; ++f)
      {
        std::array<int, 3> v = { corners_[t][(f + 1) % 4], corners_[t][(f + 2) % 4], corners_[t][(f + 3) % 4] };
        std::sort(v.begin(), v.end());
        faces.push_back({ v, 4 * t + static_cast<std::size_t>(f) });
      }
    std::sort(faces.begin(), faces.end());
    edgeInterface_.assign(nEdges_, EdgeInterface());
    for (std::size_t i = 0; i < faces.size();)
    {
      std::size_t j = i + 1;
      while (j < faces.size() && faces[j].first == faces[i].first)
        ++j;
      const std::size_t t = faces[i].second / 4, f = faces[i].second % 4;
      const int m = mesh_.tetMaterial[t];
      const int other = j - i == 1 ? kOutside : (j - i == 2 ? mesh_.tetMaterial[faces[i + 1].second / 4] : m);
      if (other != m)
        addInterfaceFace(faces[i].first, t, f, m, other);
      i = j;
    }
  }

  /// Edges of present feature-line pieces stay straight.
  void findFeatureEdges()
  {
    featureEdge_.assign(nEdges_, 0);
    for (const auto& s : mesh_.segments)
      if (s.present && s.aId >= 0 && s.bId >= 0)
      {
        const std::ptrdiff_t e = edgeIndex(s.aId, s.bId);
        if (e >= 0)
          featureEdge_[static_cast<std::size_t>(e)] = 1;
      }
  }

  /// Mid-edge nodes: the straight midpoint plus a displacement (zero unless snapped).
  void placeMidEdgeNodes(const HierarchicalOracle& oracle, QuadraticTetMesh& out)
  {
    midpoint_.assign(nEdges_, Vec3());
    displacement_.assign(nEdges_, Vec3());
    out.points = mesh_.points;
    out.points.resize(nCorners_ + nEdges_);
    out.pointDimension = mesh_.pointDimension;
    out.pointDimension.resize(nCorners_, 3);
    out.pointDimension.resize(nCorners_ + nEdges_, 3);
    for (std::size_t e = 0; e < nEdges_; ++e)
    {
      const Vec3& a = mesh_.points[edgeKeys_[e] >> 32];
      const Vec3& b = mesh_.points[edgeKeys_[e] & 0xffffffffu];
      midpoint_[e] = 0.5 * (a + b);
      int& dimension = out.pointDimension[nCorners_ + e];
      if (featureEdge_[e])
      {
        dimension = 1;
        ++features_;
        continue;
      }
      if (edgeInterface_[e].faces == 0)
        continue;
      dimension = 2;
      ++interfaceEdges_;
      snapToInterface(oracle, e, norm(b - a));
    }
  }

  /// The tetrahedra: corners, then their edges' nodes in VTK order.
  void connectTets(QuadraticTetMesh& out) const
  {
    out.tets.resize(nTets_);
    for (std::size_t t = 0; t < nTets_; ++t)
    {
      for (int c = 0; c < 4; ++c)
        out.tets[t][c] = corners_[t][c];
      for (int e = 0; e < 6; ++e)
        out.tets[t][4 + e] =
          static_cast<int>(nCorners_ + static_cast<std::size_t>(edgeIndex(corners_[t][kQuadraticTetEdges[e][0]],
                                         corners_[t][kQuadraticTetEdges[e][1]])));
    }
  }

  /// Validity: pull back the moved nodes of tetrahedra whose sampled det J is too small.
  void relax(const QuadraticTetMesh& out)
  {
    scale_.assign(nEdges_, 1.0);
    relaxed_.assign(nEdges_, 0);
    constexpr int kBisectionPasses = 4; // then straighten what still fails
    for (int pass = 0;; ++pass)
    {
      bool changed = false;
      for (std::size_t t = 0; t < nTets_; ++t)
      {
        if (!curved(out, t))
          continue;
        const std::array<double, 6> s = currentScales(out, t);
        if (quadraticTetJacobianRatio(nodesOf(out, t, s)) >= options_.minJacobianRatio)
          continue;
        relaxTet(out, t, s, pass < kBisectionPasses);
        changed = true;
      }
      if (!changed)
        break;
    }
  }

  /// The final node positions and the statistics.
  void finish(QuadraticTetMesh& out) const
  {
    double minRatio = std::numeric_limits<double>::infinity();
    for (std::size_t t = 0; t < nTets_; ++t)
      minRatio = std::min(minRatio, quadraticTetJacobianRatio(nodesOf(out, t, currentScales(out, t))));
    for (std::size_t e = 0; e < nEdges_; ++e)
      out.points[nCorners_ + e] = midpoint_[e] + scale_[e] * displacement_[e];

    auto& st = out.statistics;
    st[keys::QUADRATIC_EDGES] = static_cast<double>(nEdges_);
    st[keys::QUADRATIC_INTERFACE_EDGES] = static_cast<double>(interfaceEdges_);
    st[keys::QUADRATIC_SNAPPED_NODES] = static_cast<double>(snapped_);
    st[keys::QUADRATIC_UNSNAPPED_INTERFACE_EDGES] = static_cast<double>(unsnapped_);
    st[keys::QUADRATIC_FEATURE_EDGES] = static_cast<double>(features_);
    st[keys::QUADRATIC_RELAXED_NODES] = static_cast<double>(std::count(relaxed_.begin(), relaxed_.end(), 1));
    st[keys::QUADRATIC_MAX_SNAP_DISTANCE] = maxSnap_;
    st[keys::QUADRATIC_MIN_JACOBIAN_RATIO] = nTets_ ? minRatio : 1.0;
  }

private:
  std::ptrdiff_t edgeIndex(int a, int b) const
  {
    const auto it = std::lower_bound(edgeKeys_.begin(), edgeKeys_.end(), edgeKey(a, b));
    return it != edgeKeys_.end() && *it == edgeKey(a, b) ? it - edgeKeys_.begin() : -1;
  }

  /// Face v (sorted corners) of tetrahedron t, opposite its corner f, between materials m and other.
  void addInterfaceFace(const std::array<int, 3>& v, std::size_t t, std::size_t f, int m, int other)
  {
    const Vec3& a = mesh_.points[v[0]];
    Vec3 n = cross(mesh_.points[v[1]] - a, mesh_.points[v[2]] - a);
    const double length = norm(n);
    if (!(length > 0))
      return;
    n = (1.0 / length) * n;
    // out of tetrahedron t (away from its corner f), then from the lower material to the higher
    if (dot(n, mesh_.points[corners_[t][f]] - a) > 0)
      n = -1.0 * n;
    const int lo = std::min(m, other), hi = std::max(m, other);
    if (m != lo)
      n = -1.0 * n;
    for (int e = 0; e < 3; ++e)
    {
      auto& info = edgeInterface_[static_cast<std::size_t>(edgeIndex(v[e], v[(e + 1) % 3]))];
      if (info.faces == 0)
      {
        info.lo = lo;
        info.hi = hi;
      }
      info.samePair = info.samePair && info.lo == lo && info.hi == hi;
      info.normalSum = info.normalSum + n;
      ++info.faces;
    }
  }

  /// Interface edge e of length `length`: its mid-edge node moves to the change lo -> hi nearest
  /// the midpoint, searched both ways along the faces' normal.
  void snapToInterface(const HierarchicalOracle& oracle, std::size_t e, double length)
  {
    const EdgeInterface& info = edgeInterface_[e];
    // Two faces of one pair whose unit normals differ by less than 120 degrees (their dot product,
    // |n1 + n2|^2 / 2 - 1, above -0.5): a patch of one interface. Junctions of three materials and
    // creases stay straight (the feature lines there are straight anyway).
    const double sum = norm(info.normalSum);
    if (info.faces != 2 || !info.samePair || 0.5 * sum * sum - 1.0 < -0.5)
    {
      ++unsnapped_;
      return;
    }
    const Vec3 n = (options_.searchFraction * length / sum) * info.normalSum;
    double best = std::numeric_limits<double>::infinity();
    Vec3 found;
    for (const double side : { 1.0, -1.0 })
    {
      const Intersection hit = oracle.intersect(midpoint_[e], midpoint_[e] + side * n);
      const bool right = side > 0 ? hit.materialBefore == info.lo && hit.materialAfter == info.hi
                                  : hit.materialBefore == info.hi && hit.materialAfter == info.lo;
      if (hit.found && right && hit.t < best)
      {
        best = hit.t;
        found = hit.point;
      }
    }
    if (!std::isfinite(best))
    {
      ++unsnapped_;
      return;
    }
    displacement_[e] = found - midpoint_[e];
    if (norm(displacement_[e]) > 0)
      ++snapped_;
    maxSnap_ = std::max(maxSnap_, norm(displacement_[e]) / length);
  }

  std::size_t edgeOf(const QuadraticTetMesh& out, std::size_t t, int node) const
  {
    return static_cast<std::size_t>(out.tets[t][node]) - nCorners_;
  }

  std::array<Vec3, 10> nodesOf(const QuadraticTetMesh& out, std::size_t t, const std::array<double, 6>& s) const
  {
    std::array<Vec3, 10> x;
    for (int c = 0; c < 4; ++c)
      x[c] = mesh_.points[corners_[t][c]];
    for (int e = 0; e < 6; ++e)
    {
      const std::size_t edge = edgeOf(out, t, 4 + e);
      x[4 + e] = midpoint_[edge] + s[e] * displacement_[edge];
    }
    return x;
  }

  std::array<double, 6> currentScales(const QuadraticTetMesh& out, std::size_t t) const
  {
    std::array<double, 6> s;
    for (int e = 0; e < 6; ++e)
      s[e] = scale_[edgeOf(out, t, 4 + e)];
    return s;
  }

  bool curved(const QuadraticTetMesh& out, std::size_t t) const
  {
    for (int e = 4; e < 10; ++e)
    {
      const std::size_t edge = edgeOf(out, t, e);
      if (scale_[edge] > 0 && norm(displacement_[edge]) > 0)
        return true;
    }
    return false;
  }

  /// Scales tetrahedron t's current displacements by the largest factor that passes, found by
  /// bisection (`bisect` false, or none passing: 0, straight).
  void relaxTet(const QuadraticTetMesh& out, std::size_t t, const std::array<double, 6>& s, bool bisect)
  {
    double lo = 0.0, hi = 1.0;
    if (bisect)
      for (int step = 0; step < options_.bisectionSteps; ++step)
      {
        const double mid = 0.5 * (lo + hi);
        std::array<double, 6> trial = s;
        for (double& v : trial)
          v *= mid;
        (quadraticTetJacobianRatio(nodesOf(out, t, trial)) >= options_.minJacobianRatio ? lo : hi) = mid;
      }
    for (int e = 4; e < 10; ++e)
    {
      const std::size_t edge = edgeOf(out, t, e);
      if (scale_[edge] > 0 && norm(displacement_[edge]) > 0)
      {
        scale_[edge] *= lo;
        relaxed_[edge] = 1;
      }
    }
  }

  const TetMesh& mesh_;
  const QuadraticOptions& options_;
  const std::size_t nCorners_, nTets_;
  std::vector<std::array<int, 4>> corners_; // positively oriented
  std::vector<std::uint64_t> edgeKeys_;     // sorted
  std::size_t nEdges_ = 0;
  std::vector<EdgeInterface> edgeInterface_;
  std::vector<char> featureEdge_;
  std::vector<Vec3> midpoint_, displacement_;
  std::vector<double> scale_;
  std::vector<char> relaxed_;
  std::size_t interfaceEdges_ = 0, snapped_ = 0, unsnapped_ = 0, features_ = 0;
  double maxSnap_ = 0.0;
};
}

QuadraticTetMesh makeQuadraticTets(const TetMesh& mesh, const HierarchicalOracle& oracle, const QuadraticOptions& options)
{
  QuadraticTetMesh out;
  QuadraticTetBuilder builder(mesh, options);
  builder.findInterfaceEdges();
  builder.findFeatureEdges();
  builder.placeMidEdgeNodes(oracle, out);
  builder.connectTets(out);
  builder.relax(out);
  builder.finish(out);
  return out;
}
}
