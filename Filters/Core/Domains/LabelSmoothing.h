// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <stdexcept>
#include <vector>

namespace omesh
{
/// How a label map's smooth interfaces are estimated (LabelInterpolation::Smooth).
struct LabelSmoothingOptions
{
  /// Width (standard deviation) of the smoothing filter, in voxels along each axis.
  double sigma = 1.0;
  /// Width of a second, wider filter (in voxels, as `sigma`) whose result is taken where the
  /// surface bends little at that scale: it carries the curvature of a large ball across the flat
  /// patch of voxels at its poles, which the narrow filter leaves flat. 0 (or at most `sigma`):
  /// none.
  double wideSigma = 1.5;
  /// The flat patches the voxels leave where a surface touches a grid plane given the height of a
  /// cap fitted to the staircase around them (fitLabelPlateaus, LabelPlateauFit.h).
  bool fitPlateaus = true;
  /// Flat faces meeting at sharp edges and corners kept sharp (sharpenLabelEdges,
  /// LabelEdgeSharpening.h).
  bool sharpEdges = true;
  /// Pieces (6-connected, LabelPieces.h) of a label of at least this many voxels get an estimate
  /// of their own, so that a label on both sides of a thin layer of another keeps the layer; the
  /// smaller ones share their label's (an estimate costs about its piece's box grown by the
  /// filter's reach). 0: one estimate per label.
  int pieceVoxels = 500;
  /// Filter-and-constrain rounds per label and filter (see the .cxx).
  int iterations = 3;
  /// Pieces of a label of at most this many voxels keep their voxel volume (keepSmallPieceVolumes,
  /// SmallPieceVolumes.h); 0 = none.
  int smallPieceVoxels = 4000;
  /// Called with the fraction done; returning false stops the work (LabelSmoothingAborted).
  std::function<bool(double)> progress;
};

/// Thrown when LabelSmoothingOptions::progress asked to stop.
struct LabelSmoothingAborted : std::runtime_error
{
  LabelSmoothingAborted()
    : std::runtime_error("label map smoothing aborted")
  {
  }
};

/// Per-voxel weights w > 0 that put a label map's interfaces below the voxel size. The label at a
/// point is the one whose voxels among the 8 surrounding voxel centres carry the largest sum of
/// trilinear weight x w (w = 1 everywhere is the plain trilinear rule). Between two voxel centres
/// of labels A and B the interface then lies at w_a / (w_a + w_b) of the way, so w is fitted to
/// where a smooth estimate of each label's boundary crosses the voxel edges.
///
/// Every voxel keeps its own label at its centre (w > 0), so an interface never leaves the half
/// voxel around the voxel faces the labels allow, labels one voxel thin survive and stay
/// connected along the grid, and triple lines stay where the labels meet.
///
/// `index` holds compact labels 0 .. labelCount - 1, x fastest; `spacing` is the length of the
/// voxel axes. Only voxels with a differently labelled voxel among their 26 neighbours get a
/// fitted weight (no other voxel is the corner of a cell of two labels); the others get 1.
std::vector<float> labelInterfaceWeights(const std::array<int, 3>& dims, const std::vector<uint16_t>& index,
  int labelCount, const std::array<double, 3>& spacing, const LabelSmoothingOptions& options = {});
}
