// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include "Vec3.h"
#include "VoxelBox.h"

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

namespace omesh
{
/// Refits the values of `psi` (a signed distance on `box`, positive inside, world units, voxel
/// sizes `h`) at the `free` voxels (box offsets, increasing) so that psi's trilinear interpolant
/// follows a known surface near them: `cellSurface(free corners)` gives, for a cell of voxel
/// centres, the signed distance to the surface as its free corners see it together (an empty
/// function: none, the cell says nothing).
///
/// Values equal to the exact distances put the interpolant's zero set inside a convex edge (it is
/// below any concave function between the voxel centres: a chamfer of up to 0.34 voxel along a
/// box's edges, 0.42 at its corners). Least squares over 4^3 points in every cell of voxel centres
/// around the free voxels, weighted towards the surface (exp(-(d / half a voxel)^2)), balance the
/// chamfer against a bulge beside it (about 0.25 voxel at most). Each value keeps its voxel's side
/// of zero (`inside`, at least `delta` from it) and is held weakly to its start (where the points
/// say little). Projected Gauss-Seidel over the voxels in order.
void fitTrilinearToSurface(const VoxelBox& box, const std::array<double, 3>& h, std::vector<float>& psi,
  const std::vector<uint8_t>& inside, double delta, const std::vector<size_t>& free,
  const std::function<std::function<double(const Vec3&)>(const std::vector<size_t>&)>& cellSurface);
}
