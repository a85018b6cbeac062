// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include "VoxelBox.h"

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace omesh
{
/// How sharpenLabelEdges finds flat faces and the edges between them. Lengths in voxels (of the
/// coarsest axis), angles in degrees.
struct LabelEdgeSharpeningOptions
{
  /// Where the smooth estimate's zero set bends more than this (|Laplacian psi| per coarsest voxel,
  /// as LabelSmoothing's blend measures it) an edge may be near; elsewhere nothing is done.
  double bentCurvature = 1.2;
  /// The staircase samples within this distance of a voxel give its faces.
  int reach = 4;
  /// Samples whose normals lie within this angle start as one face.
  double faceAngle = 25.0;
  /// Faces closer in angle than this are one face: only faces that turn by at least this much
  /// make an edge (a ball's facets turn by less at any scale the voxels show).
  double edgeAngle = 60.0;
  /// A face needs this many samples.
  int minimumSamples = 6;
  /// A sample belongs to the face it lies nearest to, along its voxel edge, when within this many
  /// voxels (a plane's staircase keeps every sample within half a voxel).
  double trim = 0.7;
  /// A voxel's faces (one, or an edge's) must explain this share of the samples around it (within
  /// 0.6 voxel), and an edge's faces meet within 2.5 voxels of it.
  double explained = 0.85;
  /// Voxels this near an edge take the faces' planes.
  int near = 4;
  /// Faces of different voxels within these are one plane.
  double mergeAngle = 10.0;
  double mergeOffset = 0.5;
  /// Planes carrying less than this share of the largest plane's samples are dropped (unless
  /// found around at least `largeVoxels` voxels: a notch's faces beside a box's large ones) ...
  double significant = 0.1;
  int largeVoxels = 80;
  /// ... and planes found around fewer voxels than this (an edge needs some length) ...
  int planeVoxels = 8;
  /// ... and planes whose faces' points lie off the least-squares plane through them by more than
  /// this (RMS) or bend by more than this curvature (the largest principal curvature of a height
  /// quadric through them, 1 / radius per voxel; 1.5 times it while only the edges' own faces are
  /// known): curved faces near a crease, such as two balls crossing, sharp where they meet and
  /// round elsewhere, or a bone's shaft, round one way and straight the other.
  double flatDrift = 0.09;
  double flatCurvature = 0.03;
  /// A dropped plane found around at least this many voxels is no stray fit at a corner: the
  /// voxels near it keep psi.
  int blockingVoxels = 40;
  /// A voxel takes the planes of the voxels within this distance.
  int vote = 2;
  /// Voxels with |psi| up to this are set (outside a convex edge the staircase's distance exceeds
  /// the planes' by up to sqrt 2).
  double band = 2.0;
};

/// Where a label has flat faces meeting at sharp edges and corners (a machined part, an implant),
/// puts its smooth signed distance `psi` (positive inside, world units, on `box` with voxel sizes
/// `h`; `inside`: the label's voxels) on the faces' planes: the smoothing rounds an edge by about a
/// voxel and bulges the faces beside it, and averages a face's staircase over a voxel only.
///
/// Near voxels where the zero set bends sharply, the staircase's samples (the midpoints between a
/// voxel of the label and a 6-neighbour of another) around each voxel are grouped into faces
/// (by normal, then each sample to the plane it lies nearest) and a plane fitted to each. Where
/// two or three faces turn by at least `edgeAngle`, explain the samples and meet as a convex or a
/// concave edge, the voxel is an edge voxel. The faces of the voxels near edges are merged into
/// planes over the whole label, and every voxel near an edge takes the distance to the planes of
/// the voxels around it: their intersection at a convex edge or corner, their union at a concave
/// one, the plane alone on a face; then those values are refitted so that psi's trilinear
/// interpolant follows the planes between the voxel centres (fitTrilinearToSurface: the distances
/// alone chamfer every convex edge). Balls, shells and other smooth shapes have no such edges and
/// keep psi. Sign constraints kept (delta). Returns the number of voxels changed.
/// `scratch`: a buffer for one value per voxel of the box (its contents are lost).
std::size_t sharpenLabelEdges(const VoxelBox& box, const std::array<double, 3>& h, std::vector<float>& psi,
  const std::vector<uint8_t>& inside, double delta, std::vector<float>& scratch,
  const LabelEdgeSharpeningOptions& options = {});
}
