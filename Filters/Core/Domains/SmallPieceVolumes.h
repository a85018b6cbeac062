// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

namespace omesh
{
/// Scales the interface weights of every small piece of a label map so that the region the weights
/// give it (the labels picked as LabelInterpolation::Smooth picks them) has its voxel count's
/// volume (where they differ by more than the count's own uncertainty: each of its B boundary
/// voxels puts the count off by up to half a voxel, a standard deviation of sqrt(B / 12)). A piece
/// is a 26-connected set of voxels of one label with at most `maxVoxels` of them, away from the
/// image's border; a thin one of at least 500 voxels (fewer than a tenth of them away from other
/// labels: a shell, a plate) keeps its smooth volume. Smoothing rounds a piece's edges and corners
/// within the band the voxels allow, which is much of a piece a few voxels across (a ball of radius 2.4 voxels loses a
/// tenth of its volume, a block of 4 x 4 x 3 voxels a twentieth); a larger piece is left as it is
/// (its smooth volume is about as close to the true one as its voxel count).
///
/// `index`: compact labels, x fastest; `weights`: labelInterfaceWeights' (scaled in place: all the
/// piece's boundary voxels by one factor; every voxel centre keeps its own label). The volume is
/// sampled on 4^3 points per cell of voxel centres that the piece's label shares with others: at
/// each, the piece's label wins above one factor (the others' summed weight over its own), so the
/// factor that gives the voxel count's volume comes from these thresholds in one pass. `progress` as
/// LabelSmoothingOptions' (returning false stops: LabelSmoothingAborted).
void keepSmallPieceVolumes(const std::array<int, 3>& dims, const std::vector<uint16_t>& index,
  std::vector<float>& weights, int maxVoxels = 4000, const std::function<bool(double)>& progress = {});
}
