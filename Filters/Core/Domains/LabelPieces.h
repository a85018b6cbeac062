// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include "VoxelBox.h"

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace omesh
{
/// The 6-connected pieces of a label map's labels, kept as runs along x (a few per row of a
/// segmentation, no array per voxel). The smoothing estimates a large piece on its own: a label
/// on both sides of a thin layer of another (a hollow shell's cavity and its outside, two bones of
/// one label across a joint space) is two pieces there, each with only its own side of the layer
/// (one estimate of both mixes the two sides and thins the layer). 6-connected: a layer one voxel
/// thick separates its sides only in that sense.
class LabelPieces
{
public:
  /// `index`: compact labels, x fastest.
  LabelPieces(const std::array<int, 3>& dims, const std::vector<uint16_t>& index);

  size_t count() const { return label_.size(); }
  uint16_t label(uint32_t piece) const { return label_[piece]; }
  size_t voxels(uint32_t piece) const { return voxels_[piece]; }
  /// The piece of voxel v (x fastest).
  uint32_t at(size_t v) const;
  /// inside[o] = 1 where the voxel at the box's offset o belongs to `piece`, else 0.
  void fill(const VoxelBox& box, uint32_t piece, std::vector<uint8_t>& inside) const;

private:
  std::array<int, 3> dims_;
  std::vector<uint32_t> rowFirst_; ///< per row (y + ny z) its first run; one more at the end
  std::vector<int> runX_;          ///< where each run begins along x (it ends where the next does)
  std::vector<uint32_t> runPiece_;
  std::vector<uint16_t> label_;
  std::vector<size_t> voxels_;
};
}
