// SPDX-License-Identifier: GPL-3.0-or-later
#include "FeatureEdgeSizes.h"

#include "HierarchicalOracle.h"

#include <algorithm>
#include <cmath>

namespace omesh
{
double featureEdgeSize(std::optional<double> own, const std::vector<int>& materials, const MaterialCriteria& criteria)
{
  if (own)
    return *own;
  std::optional<double> finest;
  for (int m : materials)
  {
    const auto it = criteria.perMaterial.find(m);
    if (m == kOutside || it == criteria.perMaterial.end() || !it->second.edgeSize)
      continue;
    const double v = *it->second.edgeSize;
    // 0 (no bound) is the coarsest: any positive bound of another material is finer
    if (!finest || (v > 0 && (*finest <= 0 || v < *finest)))
      finest = v;
  }
  return finest ? *finest : criteria.globalValues().edgeSize;
}

bool hasMaterialEdgeSizes(const MaterialCriteria& criteria)
{
  return std::any_of(criteria.perMaterial.begin(), criteria.perMaterial.end(),
    [](const auto& mc) { return mc.second.edgeSize.has_value(); });
}

std::vector<int> materialsAroundSegment(const HierarchicalOracle& oracle, const Vec3& a, const Vec3& b)
{
  const Vec3 d = b - a;
  const double length = norm(d);
  Vec3 u, v;
  perpendicularPair((1.0 / length) * d, u, v);
  const double r = 1e-3 * length;
  std::vector<int> out;
  auto add = [&](const Vec3& p) {
    const int m = oracle.material(p);
    if (m != kOutside)
      out.push_back(m);
  };
  for (double t : { 0.25, 0.5, 0.75 })
  {
    const Vec3 c = lerp(a, b, t);
    add(c);
    for (int k = 0; k < 16; ++k)
    {
      const double phi = 2.0 * M_PI * k / 16.0;
      add(c + (r * std::cos(phi)) * u + (r * std::sin(phi)) * v);
    }
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

std::vector<double> resolveFeatureEdgeSizes(
  const FeatureSegments& features, const MaterialCriteria& criteria, const HierarchicalOracle& oracle)
{
  const bool byMaterial = hasMaterialEdgeSizes(criteria);
  std::vector<double> out(features.segments.size());
  for (size_t s = 0; s < features.segments.size(); ++s)
  {
    const std::optional<double> own = features.edgeSize(s);
    std::vector<int> materials;
    if (!own && byMaterial)
      materials = materialsAroundSegment(oracle, features.points[features.segments[s][0]], features.points[features.segments[s][1]]);
    out[s] = featureEdgeSize(own, materials, criteria);
  }
  return out;
}
}
