// SPDX-License-Identifier: GPL-3.0-or-later
#include "MeshSizeEstimate.h"

#include "FeatureEdgeSizes.h"
#include "HierarchicalOracle.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <vector>

namespace omesh
{
namespace
{
double orDefault(double v, double fallback) { return v > 0 ? v : fallback; }

constexpr int kSamples = 24; // grid cells along each axis of the oracle's bounds

/// The oracle's material at the centres of a kSamples^3 grid over its bounds (index (k n + j) n + i).
std::vector<int> sampleMaterials(const HierarchicalOracle& oracle, const BoundingBox& box)
{
  constexpr int n = kSamples;
  const Vec3 step = (1.0 / n) * box.size();
  std::vector<int> label(static_cast<size_t>(n) * n * n);
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        label[(static_cast<size_t>(k) * n + j) * n + i] =
          oracle.material(box.min + Vec3{ (i + 0.5) * step.x, (j + 0.5) * step.y, (k + 0.5) * step.z });
  return label;
}

double cellVertices(const std::vector<int>& label, const BoundingBox& box, const MaterialCriteria& criteria)
{
  const Vec3 step = (1.0 / kSamples) * box.size();
  std::map<int, double> volume;
  for (int m : label)
    if (m != kOutside)
      volume[m] += step.x * step.y * step.z;
  double vertices = 0.0;
  for (const auto& [m, v] : volume)
  {
    const double cell = orDefault(criteria.of(m).cellSize, norm(box.size()) / 20.0);
    vertices += v / (cell * cell * cell);
  }
  return vertices;
}
}

double estimateCellVertices(const HierarchicalOracle& oracle, const MaterialCriteria& criteria)
{
  const BoundingBox box = oracle.bounds();
  return cellVertices(sampleMaterials(oracle, box), box, criteria);
}

double estimateMeshVertices(const HierarchicalOracle& oracle, const MaterialCriteria& criteria,
  const FeatureSegments& features)
{
  const BoundingBox box = oracle.bounds();
  const double fallback = norm(box.size()) / 20.0;
  constexpr int n = kSamples;
  const Vec3 step = (1.0 / n) * box.size();
  const std::vector<int> label = sampleMaterials(oracle, box);
  auto at = [&](int i, int j, int k) { return label[(static_cast<size_t>(k) * n + j) * n + i]; };

  // Interface area per material (a staircase over-counts a slanted area by at most sqrt(3), and
  // the box's own faces count as boundary).
  std::map<int, double> area;
  const double faceArea[3] = { step.y * step.z, step.x * step.z, step.x * step.y };
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
      {
        const int m = at(i, j, k);
        const int next[3] = { i + 1 < n ? at(i + 1, j, k) : kOutside, j + 1 < n ? at(i, j + 1, k) : kOutside,
          k + 1 < n ? at(i, j, k + 1) : kOutside };
        const int index[3] = { i, j, k };
        for (int axis = 0; axis < 3; ++axis)
        {
          if (next[axis] != m)
            for (int side : { m, next[axis] })
              if (side != kOutside)
                area[side] += faceArea[axis];
          if (index[axis] == 0 && m != kOutside)
            area[m] += faceArea[axis];
        }
      }

  double vertices = cellVertices(label, box, criteria);
  for (const auto& [m, a] : area)
  {
    const MeshCriteria::Values c = criteria.of(m);
    const double facet = orDefault(c.facetSize, orDefault(c.cellSize, fallback));
    // triangles of circumradius `facet` have an area of about 1.3 facet^2; two per vertex
    vertices += a / (2.6 * facet * facet);
  }
  // each segment at its own edge size (global < per material < per feature, FeatureEdgeSizes.h)
  const std::vector<double> edges = resolveFeatureEdgeSizes(features, criteria, oracle);
  for (size_t s = 0; s < features.segments.size(); ++s)
    vertices += features.length(s) / (edges[s] > 0 ? edges[s] : fallback);
  return vertices;
}
}
