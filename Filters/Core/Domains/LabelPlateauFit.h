// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include "VoxelBox.h"

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

namespace omesh
{
/// How fitLabelPlateaus finds the flat patches a label's voxels leave where its surface touches a
/// grid plane, and when it trusts the cap fitted over one.
struct LabelPlateauOptions
{
  /// Terraces (patches neither on a hill's top nor in a pit) with fewer voxels than this whose
  /// four in-plane neighbours lie in the patch too are left to the filters.
  int minimumInterior = 3;
  /// The cap is fitted to the staircase's walls up to about this far beyond the patch's rim (in
  /// voxels of the coarsest axis) ...
  double margin = 3.0;
  /// ... on this many layers beyond the patch's on either side.
  int layers = 3;
  /// A cap the walls miss by more than this many times their own uncertainty (RMS) is no cap: a
  /// box's face and its sides, a ridge, two parts close together.
  double consistency = 1.5;
  /// At most this slope over the patch.
  double maximumSlope = 1.5;
};

/// Where a label's surface touches a grid plane (a ball's pole on a grid axis, a condyle on a CT
/// slice), its voxels leave a flat patch: their centres say only that the surface lies between
/// the patch's layer and the next, and the smoothing filters, which reach a few voxels, keep it
/// nearly flat half way: up to half a voxel (of that axis) off where the pole almost reaches the
/// next layer or barely passes the patch's, the worst places of a ball's surface.
///
/// The staircase's walls around the patch tell more: a wall between two columns of different
/// heights says that the surface passes that layer between them, at an exact height and within
/// half a voxel sideways, which moves the height little where the surface is nearly level. A cap
/// (a quadric surface with its axis along the grid's, a ball's cap down to its equator exactly)
/// fitted to the walls, each weighted by how much its sideways error moves it, gives the surface
/// over the patch; `psi` (a signed distance on `box`, positive `inside`, world units, voxel sizes
/// `h`) over the patch becomes the distance to it, at least `delta` on its voxel's side of zero.
///
/// Patches on the top of a hill or the bottom of a pit (every neighbouring column lower, or every
/// one higher) are fitted at any size, with their rim; the terraces of a tilted or curved surface
/// when they are wide (the filters follow planes). A cap lies between the label and one other
/// (`other(box offset)`: the label of a voxel outside it): walls to a third label belong to
/// another interface. Nothing changes where the walls do not agree with one cap (a box's corner,
/// a crease), or the cap leaves the patch's layers or is steep there.
void fitLabelPlateaus(const VoxelBox& box, const std::array<double, 3>& h, std::vector<float>& psi,
  const std::vector<uint8_t>& inside, const std::function<int(size_t)>& other, double delta,
  const LabelPlateauOptions& options = {});
}
