// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include "AffineMap.h"
#include "Domain.h"
#include "LabelSmoothing.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <map>

namespace omesh
{
/// How a label map is read between voxel centres.
enum class LabelInterpolation
{
  /// Voxel (i, j, k) owns the half-open cell [i, i+1) x [j, j+1) x [k, k+1) of continuous voxel
  /// coordinates, the grid's outer faces included: material boundaries are voxel staircases.
  Nearest,
  /// The label whose indicator function, interpolated trilinearly between the 8 nearest voxel
  /// centres, is largest (as CGAL's labelled image domains): smooth material boundaries, which
  /// mesh without the flat tetrahedra a staircase forces on the interfaces.
  Trilinear,
  /// As Trilinear, each voxel centre weighted (labelInterfaceWeights) so that the interfaces
  /// follow a smooth estimate of the labels' boundaries below the voxel size, inside the band
  /// the voxels allow: no staircase on flat or curved faces, thin layers kept.
  Smooth
};

/// A uniform grid of voxels, each carrying an integer label; every label other than the background is
/// a material (material id = label). The grid's outer faces bound every material.
class LabelMapDomain : public Domain
{
public:
  /// `worldToVoxel` maps world points to continuous voxel coordinates; labels are x-fastest.
  /// Throws InputError (naming `name`) for an empty grid, a size mismatch, negative labels, more
  /// than 65535 distinct labels or a singular map.
  LabelMapDomain(const std::array<int, 3>& dims, const std::vector<int>& labels,
    const AffineMap& worldToVoxel, int backgroundLabel, const std::string& name = "LabelMap",
    LabelInterpolation interpolation = LabelInterpolation::Nearest, const LabelSmoothingOptions& smoothing = {});

  /// The two conventions images come in. Point scalars: each point is the centre of its voxel (ITK,
  /// CGAL Image_3). Cell scalars: each cell is a voxel. `direction` is row-major 3x3 (VTK/ITK).
  static AffineMap pointCenteredWorldToVoxel(const Vec3& origin, const Vec3& spacing,
    const std::array<double, 9>& direction);
  static AffineMap cellCenteredWorldToVoxel(const Vec3& origin, const Vec3& spacing,
    const std::array<double, 9>& direction);

  int material(const Vec3& p) const override
  {
    const Vec3 u = worldToVoxel_.apply(p);
    if (!(u.x >= 0.0 && u.y >= 0.0 && u.z >= 0.0 && u.x <= dimsD_[0] && u.y <= dimsD_[1] &&
          u.z <= dimsD_[2]))
      return kOutside;
    return indexMaterial_[interpolation_ == LabelInterpolation::Nearest ? index_[voxelOf(u)] : trilinearIndex(u)];
  }
  void crossings(const Vec3& a, const Vec3& b, std::vector<double>& ts) const override
  {
    firstCrossings(a, b, ts, std::numeric_limits<int>::max());
  }
  /// Trilinear: the walk stops after the piece where it found the first `changes` changes; true
  /// when ab lies in the grid and every piece of it was shown to keep the start's label (cells of
  /// one label, the lead's cubic), none sampled.
  bool firstCrossings(const Vec3& a, const Vec3& b, std::vector<double>& ts, int changes) const override;
  /// Trilinear: answered where the walk sampled no piece up to its first change (cells of one
  /// label, the lead's cubic in cells of two labels; see trilinearCrossings), the grid's
  /// boundary included (outside it every point is outside).
  bool firstChange(const Vec3& a, const Vec3& b, ShownChange& shown, std::vector<double>& ts,
    bool& candidatesShown) const override;
  /// The planes through voxel centres (Trilinear) or voxel faces (Nearest) that ab crosses.
  void bendPlanes(const Vec3& a, const Vec3& b, std::vector<BendPlane>& planes) const override;
  BoundingBox bounds() const override;
  const char* kind() const override { return "LabelMap"; }
  std::vector<int> materials() const override;

  LabelInterpolation interpolation() const { return interpolation_; }

  /// Number of voxels per material (background excluded) and the volume of one voxel: the exact
  /// material volumes the oracle represents with Nearest interpolation.
  std::map<int, size_t> voxelCounts() const;
  double voxelVolume() const { return voxelVolume_; }
  const std::array<int, 3>& dims() const { return dims_; }

private:
  size_t voxelOf(const Vec3& u) const
  {
    const int i = std::min(static_cast<int>(u.x), dims_[0] - 1);
    const int j = std::min(static_cast<int>(u.y), dims_[1] - 1);
    const int k = std::min(static_cast<int>(u.z), dims_[2] - 1);
    return static_cast<size_t>(i) + static_cast<size_t>(dims_[0]) * (static_cast<size_t>(j) + static_cast<size_t>(dims_[1]) * k);
  }

  /// Voxel coordinates moved onto the grid [0, dims] (for points on the grid's faces).
  Vec3 clampToGrid(const Vec3& u) const
  {
    return { std::clamp(u.x, 0.0, dimsD_[0]), std::clamp(u.y, 0.0, dimsD_[1]), std::clamp(u.z, 0.0, dimsD_[2]) };
  }
  /// Compact label index of the largest trilinear indicator at voxel coordinates u (in the grid).
  uint16_t trilinearIndex(const Vec3& u) const;
  /// What a walk found besides its crossings.
  struct WalkReport
  {
    uint16_t start = 0;      ///< the label at its start
    bool sampled = false;    ///< some piece's label was sampled (four samples and searches)
    uint16_t afterFirst = 0; ///< the label after its first crossing, or its last label without one
  };
  /// The walk along ua + t d, t in [t0, t1] (on the grid): appends the changes of label (see the
  /// definition) and returns whether it showed the start's label to hold all along, no piece sampled.
  bool trilinearCrossings(const Vec3& ua, const Vec3& d, double t0, double t1, int changes, std::vector<double>& ts,
    WalkReport* report = nullptr) const;
  /// Fills clearance_ (Trilinear and Smooth).
  void buildClearance();

  std::array<int, 3> dims_;
  std::array<double, 3> dimsD_;
  std::vector<uint16_t> index_;    ///< compact label index per voxel (2 bytes a voxel)
  std::vector<int> indexMaterial_; ///< compact index -> material id (kOutside for the background)
  /// Per cell of voxel centres (dims + 1 per axis, with one padding cell on each side; cell c's
  /// lower corner is voxel c - 1, clamped): the Chebyshev distance in cells to the nearest cell whose
  /// 8 corners carry more than one label, 0 for such a mixed cell, capped at 255. A cell
  /// at distance D is the centre of a cube of 2D - 1 cells of one label (adjacent uniform cells
  /// share corners): the crossings' walk tells a piece of one label with one load and jumps over
  /// the cube. 1 byte a cell (Trilinear only).
  std::vector<uint8_t> clearance_;
  /// Smooth: per voxel the weight of its centre in the trilinear sums (labelInterfaceWeights), 4
  /// bytes a voxel; empty otherwise.
  std::vector<float> weights_;
  std::array<size_t, 3> clearanceStride_{};
  AffineMap worldToVoxel_;
  double voxelVolume_ = 0.0;
  LabelInterpolation interpolation_ = LabelInterpolation::Nearest;
};
}
