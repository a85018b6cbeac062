// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <cmath>
#include <limits>
#include <map>

namespace omesh
{
/// Delaunay-refinement criteria (paper section 2 / CGAL Mesh_3). A value <= 0 means "no bound".
/// In per-material overrides a NaN field means "inherit the global value".
struct MeshCriteria
{
  static constexpr double kInherit = std::numeric_limits<double>::quiet_NaN();

  double facetAngle = 25.0;         ///< lower bound of facet angles, degrees (<= 30 for termination)
  double facetSize = 0.0;           ///< upper bound of the surface Delaunay ball radius
  double facetDistance = 0.0;       ///< upper bound of facet-centre-to-surface distance
  double cellSize = 0.0;            ///< upper bound of the tetrahedron circumradius
  double cellRadiusEdgeRatio = 3.0; ///< upper bound of circumradius / shortest edge (>= 2 guaranteed)
  double edgeSize = 0.0;            ///< upper bound of constrained-segment length

  static MeshCriteria inheritAll()
  {
    return { kInherit, kInherit, kInherit, kInherit, kInherit, kInherit };
  }
  /// This, with every NaN field taken from `base`.
  MeshCriteria over(const MeshCriteria& base) const
  {
    auto pick = [](double mine, double theirs) { return std::isnan(mine) ? theirs : mine; };
    return { pick(facetAngle, base.facetAngle), pick(facetSize, base.facetSize),
      pick(facetDistance, base.facetDistance), pick(cellSize, base.cellSize),
      pick(cellRadiusEdgeRatio, base.cellRadiusEdgeRatio), pick(edgeSize, base.edgeSize) };
  }
};

/// Global criteria plus per-material overrides (NaN fields inherit).
struct MaterialCriteria
{
  MeshCriteria global;
  std::map<int, MeshCriteria> perMaterial;

  MeshCriteria of(int material) const
  {
    auto it = perMaterial.find(material);
    return it == perMaterial.end() ? global : it->second.over(global);
  }
};
}
