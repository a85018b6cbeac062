// SPDX-License-Identifier: GPL-3.0-or-later
// One segment's walk through the cells of voxel centres of a label map read trilinearly
// (LabelMapDomain::trilinearCrossings): the label at a point of it, the cubic of a label's lead
// along a piece, the last point where a label holds. The lookups made for every piece are inline
// here, the searches in TrilinearWalk.cxx.
#pragma once

#include "Vec3.h"
#include "VoxelCorners.h"

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>

namespace omesh
{
/// One segment's walk through the cells of voxel centres (continuous voxel coordinates ua + t d).
/// The 8 labels around the last point looked at stay loaded: the samples and the search inside
/// one cell only recompute the weights (the answers are those of trilinearIndex at every point).
class TrilinearWalk
{
public:
  TrilinearWalk(const std::array<int, 3>& dims, const uint16_t* index, const float* weights, const uint8_t* clearance,
    const std::array<size_t, 3>& clearanceStride, const Vec3& ua, const Vec3& d)
    : dims_(dims)
    , index_(index)
    , weights_(weights)
    , clearance_(clearance)
    , clearanceStride_(clearanceStride)
    , ua_(ua)
    , d_(d)
  {
  }

  /// The cell of t (its lower corner lo) and t's fractions in it.
  void cellAt(double t, int lo[3], double f[3]) const
  {
    const Vec3 u = ua_ + t * d_;
    const Vec3 c{ std::clamp(u.x, 0.0, double(dims_[0])), std::clamp(u.y, 0.0, double(dims_[1])),
      std::clamp(u.z, 0.0, double(dims_[2])) };
    splitCell(c, lo, f);
  }

  /// Loads the cell of t; f gets t's fractions in it.
  void cornersAt(double t, double f[3])
  {
    int lo[3];
    cellAt(t, lo, f);
    if (!sameCell(lo, cache_.lo))
      loadCorners(dims_, index_, weights_, lo, cache_);
    distinctLabels(cache_); // for the weights of its labels
  }

  /// The clearance of the cell of t (0: mixed) and, when it is not mixed, its one label. lo gets
  /// the cell's lower corner.
  int clearanceAt(double t, int lo[3], uint16_t& label) const
  {
    double f[3];
    cellAt(t, lo, f);
    const int c = clearance_[clearanceOffset(clearanceStride_, lo)];
    if (c != 0)
      label = index_[lowerCorner(dims_, lo)];
    return c;
  }

  /// Bernstein coefficients of how far `label` leads along the piece [a, b] (in `cell`, the cell
  /// of its midpoint, which this loads; a mixed cell): the trilinear interpolant of +1 at the corners
  /// of `label`, -1 at the others, a cubic along the piece. In a cell of two labels, `label` one
  /// of them, that is exactly its lead over the other (its indicator minus the other's), so the
  /// label changes where the cubic changes sign: true. With more labels it is 2 chi - 1 (chi its
  /// indicator), above 0 only where `label` certainly wins: false.
  bool leadOnPiece(double a, double b, const int cell[3], uint16_t label, double lead[4]);

  /// The label other than `label` of the cell leadOnPiece loaded last (a cell of two labels, one
  /// of them `label`).
  uint16_t otherLabel() const { return other_; }

  /// Where the segment leaves the cube of cells around cell lo that a clearance of D says are of
  /// one label: the parameter of a plane through voxel centres, computed as PieceEnds computes it.
  double exitOfCube(const int lo[3], int D) const
  {
    double t = std::numeric_limits<double>::infinity();
    for (int a = 0; a < 3; ++a)
    {
      if (d_[a] == 0.0)
        continue;
      const double k = static_cast<double>(d_[a] > 0.0 ? lo[a] + D : lo[a] + 1 - D);
      t = std::min(t, (k + 0.5 - ua_[a]) / d_[a]);
    }
    return t;
  }

  uint16_t labelAt(double t)
  {
    double f[3];
    cornersAt(t, f);
    return pickLabel(cache_, f);
  }

  /// The label at t where the walk starts, and whether the segment up to t1 stays in the cube of
  /// cells of that one label around t's cell (then nothing can change along it).
  uint16_t labelAtStart(double t, double t1, bool& noChange);

  /// The last t where `label` holds between lo (it holds) and hi (it does not), to 1e-12: a
  /// bracketing search (Illinois regula falsi on the label's lead, a bisection whenever three
  /// steps do not halve the bracket) that keeps the bisection's answer to its tolerance with about
  /// a fifth of its label evaluations.
  double lastOf(uint16_t label, double lo, double hi);

private:
  /// The label at t and how far `label` leads there.
  double leadAt(double t, uint16_t label, uint16_t& at);

  /// A little past the interpolated root, away from the end that moved last: once the root is
  /// known to the tolerance, that closes the bracket in one step. A lead of exactly 0 is a tie
  /// decided by index: the change is most likely right at that end. `fallback` if outside.
  static double interpolated(double lo, double hi, double gLo, double gHi, int side, double fallback);

  const std::array<int, 3>& dims_;
  const uint16_t* index_;
  const float* weights_; ///< interface weights per voxel (Smooth), or null
  const uint8_t* clearance_;
  const std::array<size_t, 3>& clearanceStride_;
  Vec3 ua_, d_;
  VoxelCorners cache_;
  uint16_t other_ = 0; ///< leadOnPiece's other label
};
}
