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

QuadraticTetMesh makeQuadraticTets(const TetMesh& mesh, const HierarchicalOracle& oracle, const QuadraticOptions& options)
{
  QuadraticTetMesh out;
  const std::size_t nCorners = mesh.points.size();
  const std::size_t nTets = mesh.tets.size();
  std::vector<std::array<int, 4>> corners(mesh.tets);
  for (auto& k : corners)
    if (signedVolume(mesh.points[k[0]], mesh.points[k[1]], mesh.points[k[2]], mesh.points[k[3]]) < 0)
      std::swap(k[0], k[1]);

  // Edges: sorted keys, so node ids do not depend on the tetrahedra's order.
  std::vector<std::uint64_t> keys;
  keys.reserve(6 * nTets);
  for (const auto& k : corners)
    for (const auto& e : kQuadraticTetEdges)
      keys.push_back(edgeKey(k[e[0]], k[e[1]]));
  std::sort(keys.begin(), keys.end());
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  const auto edgeIndex = [&keys](int a, int b) -> std::ptrdiff_t {
    const auto it = std::lower_bound(keys.begin(), keys.end(), edgeKey(a, b));
    return it != keys.end() && *it == edgeKey(a, b) ? it - keys.begin() : -1;
  };
  const std::size_t nEdges = keys.size();

  // Interface faces (between two materials, or a material and the outside) and their edges.
  std::vector<std::pair<std::array<int, 3>, std::size_t>> faces; // sorted corner ids, 4 tet + face
  faces.reserve(4 * nTets);
  for (std::size_t t = 0; t < nTets; ++t)
    for (int f = 0; f < 4; ++f)
    {
      std::array<int, 3> v = { corners[t][(f + 1) % 4], corners[t][(f + 2) % 4], corners[t][(f + 3) % 4] };
      std::sort(v.begin(), v.end());
      faces.push_back({ v, 4 * t + static_cast<std::size_t>(f) });
    }
  std::sort(faces.begin(), faces.end());
  std::vector<EdgeInterface> edgeInterface(nEdges);
  for (std::size_t i = 0; i < faces.size();)
  {
    std::size_t j = i + 1;
    while (j < faces.size() && faces[j].first == faces[i].first)
      ++j;
    const std::size_t t = faces[i].second / 4, f = faces[i].second % 4;
    const int m = mesh.tetMaterial[t];
    const int other = j - i == 1 ? kOutside : (j - i == 2 ? mesh.tetMaterial[faces[i + 1].second / 4] : m);
    if (other != m)
    {
      const auto& v = faces[i].first;
      const Vec3& a = mesh.points[v[0]];
      Vec3 n = cross(mesh.points[v[1]] - a, mesh.points[v[2]] - a);
      const double length = norm(n);
      if (length > 0)
      {
        n = (1.0 / length) * n;
        // out of tetrahedron t (away from its corner f), then from the lower material to the higher
        if (dot(n, mesh.points[corners[t][f]] - a) > 0)
          n = -1.0 * n;
        const int lo = std::min(m, other), hi = std::max(m, other);
        if (m != lo)
          n = -1.0 * n;
        for (int e = 0; e < 3; ++e)
        {
          auto& info = edgeInterface[static_cast<std::size_t>(edgeIndex(v[e], v[(e + 1) % 3]))];
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
    }
    i = j;
  }

  std::vector<char> featureEdge(nEdges, 0);
  for (const auto& s : mesh.segments)
    if (s.present && s.aId >= 0 && s.bId >= 0)
    {
      const std::ptrdiff_t e = edgeIndex(s.aId, s.bId);
      if (e >= 0)
        featureEdge[static_cast<std::size_t>(e)] = 1;
    }

  // Mid-edge nodes: the straight midpoint plus a displacement (zero unless snapped).
  std::vector<Vec3> midpoint(nEdges), displacement(nEdges);
  out.points = mesh.points;
  out.points.resize(nCorners + nEdges);
  out.pointDimension = mesh.pointDimension;
  out.pointDimension.resize(nCorners, 3);
  out.pointDimension.resize(nCorners + nEdges, 3);
  std::size_t interfaceEdges = 0, snapped = 0, unsnapped = 0, features = 0;
  double maxSnap = 0.0;
  for (std::size_t e = 0; e < nEdges; ++e)
  {
    const Vec3& a = mesh.points[keys[e] >> 32];
    const Vec3& b = mesh.points[keys[e] & 0xffffffffu];
    midpoint[e] = 0.5 * (a + b);
    const EdgeInterface& info = edgeInterface[e];
    int& dimension = out.pointDimension[nCorners + e];
    if (featureEdge[e])
    {
      dimension = 1;
      ++features;
      continue;
    }
    if (info.faces == 0)
      continue;
    dimension = 2;
    ++interfaceEdges;
    // Two faces of one pair whose unit normals differ by less than 120 degrees (their dot product,
    // |n1 + n2|^2 / 2 - 1, above -0.5): a patch of one interface. Junctions of three materials and
    // creases stay straight (the feature lines there are straight anyway).
    const double sum = norm(info.normalSum);
    if (info.faces != 2 || !info.samePair || 0.5 * sum * sum - 1.0 < -0.5)
    {
      ++unsnapped;
      continue;
    }
    const Vec3 n = (options.searchFraction * norm(b - a) / sum) * info.normalSum;
    // The change lo -> hi nearest the midpoint, searched both ways from it.
    double best = std::numeric_limits<double>::infinity();
    Vec3 found;
    for (const double side : { 1.0, -1.0 })
    {
      const Intersection hit = oracle.intersect(midpoint[e], midpoint[e] + side * n);
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
      ++unsnapped;
      continue;
    }
    displacement[e] = found - midpoint[e];
    if (norm(displacement[e]) > 0)
      ++snapped;
    maxSnap = std::max(maxSnap, norm(displacement[e]) / norm(b - a));
  }

  out.tets.resize(nTets);
  for (std::size_t t = 0; t < nTets; ++t)
  {
    for (int c = 0; c < 4; ++c)
      out.tets[t][c] = corners[t][c];
    for (int e = 0; e < 6; ++e)
      out.tets[t][4 + e] =
        static_cast<int>(nCorners + static_cast<std::size_t>(edgeIndex(corners[t][kQuadraticTetEdges[e][0]],
                                      corners[t][kQuadraticTetEdges[e][1]])));
  }

  // Validity: pull back the moved nodes of tetrahedra whose sampled det J is too small.
  std::vector<double> scale(nEdges, 1.0);
  const auto nodesOf = [&](std::size_t t, const std::array<double, 6>& s) {
    std::array<Vec3, 10> x;
    for (int c = 0; c < 4; ++c)
      x[c] = mesh.points[corners[t][c]];
    for (int e = 0; e < 6; ++e)
    {
      const std::size_t edge = static_cast<std::size_t>(out.tets[t][4 + e]) - nCorners;
      x[4 + e] = midpoint[edge] + s[e] * displacement[edge];
    }
    return x;
  };
  const auto currentScales = [&](std::size_t t) {
    std::array<double, 6> s;
    for (int e = 0; e < 6; ++e)
      s[e] = scale[static_cast<std::size_t>(out.tets[t][4 + e]) - nCorners];
    return s;
  };
  const auto curved = [&](std::size_t t) {
    for (int e = 4; e < 10; ++e)
    {
      const std::size_t edge = static_cast<std::size_t>(out.tets[t][e]) - nCorners;
      if (scale[edge] > 0 && norm(displacement[edge]) > 0)
        return true;
    }
    return false;
  };
  std::vector<char> relaxed(nEdges, 0);
  constexpr int kBisectionPasses = 4; // then straighten what still fails
  for (int pass = 0;; ++pass)
  {
    bool changed = false;
    for (std::size_t t = 0; t < nTets; ++t)
    {
      if (!curved(t))
        continue;
      const std::array<double, 6> s = currentScales(t);
      if (quadraticTetJacobianRatio(nodesOf(t, s)) >= options.minJacobianRatio)
        continue;
      // The largest factor on this tetrahedron's current displacements that passes (0 does: straight).
      double lo = 0.0, hi = 1.0;
      if (pass < kBisectionPasses)
        for (int step = 0; step < options.bisectionSteps; ++step)
        {
          const double mid = 0.5 * (lo + hi);
          std::array<double, 6> trial = s;
          for (double& v : trial)
            v *= mid;
          (quadraticTetJacobianRatio(nodesOf(t, trial)) >= options.minJacobianRatio ? lo : hi) = mid;
        }
      for (int e = 4; e < 10; ++e)
      {
        const std::size_t edge = static_cast<std::size_t>(out.tets[t][e]) - nCorners;
        if (scale[edge] > 0 && norm(displacement[edge]) > 0)
        {
          scale[edge] *= lo;
          relaxed[edge] = 1;
        }
      }
      changed = true;
    }
    if (!changed)
      break;
  }

  double minRatio = std::numeric_limits<double>::infinity();
  for (std::size_t t = 0; t < nTets; ++t)
    minRatio = std::min(minRatio, quadraticTetJacobianRatio(nodesOf(t, currentScales(t))));
  for (std::size_t e = 0; e < nEdges; ++e)
    out.points[nCorners + e] = midpoint[e] + scale[e] * displacement[e];

  auto& st = out.statistics;
  st[keys::QUADRATIC_EDGES] = static_cast<double>(nEdges);
  st[keys::QUADRATIC_INTERFACE_EDGES] = static_cast<double>(interfaceEdges);
  st[keys::QUADRATIC_SNAPPED_NODES] = static_cast<double>(snapped);
  st[keys::QUADRATIC_UNSNAPPED_INTERFACE_EDGES] = static_cast<double>(unsnapped);
  st[keys::QUADRATIC_FEATURE_EDGES] = static_cast<double>(features);
  st[keys::QUADRATIC_RELAXED_NODES] = static_cast<double>(std::count(relaxed.begin(), relaxed.end(), 1));
  st[keys::QUADRATIC_MAX_SNAP_DISTANCE] = maxSnap;
  st[keys::QUADRATIC_MIN_JACOBIAN_RATIO] = nTets ? minRatio : 1.0;
  return out;
}
}
