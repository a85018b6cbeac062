// SPDX-License-Identifier: GPL-3.0-or-later
// The 8 voxel centres around a point of a label map read trilinearly, and the label the weights
// of their labels pick there: shared by LabelMapDomain::trilinearIndex and TrilinearWalk. Inline
// in a header: they run for every query, several times per cell a segment crosses.
#pragma once

#include "Vec3.h"

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>

namespace omesh
{
/// floor(x) for x >= -1, as std::floor, without its library call (the x86-64 baseline has no
/// rounding instruction; the call was 7 % of a label map's meshing): truncation of x + 1 is
/// floor(x) + 1 or, where the sum rounded up to the next integer, one more.
inline int floorAboveMinusOne(double x)
{
  int i = static_cast<int>(x + 1.0) - 1;
  if (static_cast<double>(i) > x)
    --i;
  return i;
}

/// The 8 voxel centres around a point: lower corner `lo` (may lie outside the grid; indices are
/// clamped at the border) and their compact label indices. Within one cell of voxel centres they
/// do not change, so a walk along a segment loads them once per cell.
struct VoxelCorners
{
  int lo[3] = { std::numeric_limits<int>::min(), 0, 0 };
  uint16_t idx[8] = {};
  float w[8] = { 1, 1, 1, 1, 1, 1, 1, 1 }; ///< the corners' interface weights (Smooth; else 1)
  bool uniform = false;
  // the distinct labels in order of first appearance, and each corner's place among them (a mixed
  // cell's, once distinctLabels has run: the lead's cubic needs only idx)
  bool slotted = false;
  int distinctCount = 0;
  uint16_t distinct[8] = {};
  uint8_t slot[8] = {};
};

/// Lower voxel-centre corner and fractions of u (continuous voxel coordinates, on the grid).
inline void splitCell(const Vec3& u, int lo[3], double f[3])
{
  for (int a = 0; a < 3; ++a)
  {
    const double x = u[a] - 0.5;
    lo[a] = floorAboveMinusOne(x);
    f[a] = x - lo[a];
  }
}

inline bool sameCell(const int a[3], const int b[3]) { return a[0] == b[0] && a[1] == b[1] && a[2] == b[2]; }

/// Voxel offset of a cell's corner 0 (its lower corner lo, clamped to the grid).
inline size_t lowerCorner(const std::array<int, 3>& dims, const int lo[3])
{
  return static_cast<size_t>(std::max(lo[0], 0)) +
    static_cast<size_t>(dims[0]) *
    (static_cast<size_t>(std::max(lo[1], 0)) + static_cast<size_t>(dims[1]) * static_cast<size_t>(std::max(lo[2], 0)));
}

/// Offset of the cell with lower corner lo (-1 .. dims - 1) in the padded clearance array.
inline size_t clearanceOffset(const std::array<size_t, 3>& stride, const int lo[3])
{
  return static_cast<size_t>(lo[0] + 2) + stride[1] * static_cast<size_t>(lo[1] + 2) +
    stride[2] * static_cast<size_t>(lo[2] + 2);
}

inline void loadCorners(
  const std::array<int, 3>& dims, const uint16_t* index, const float* weights, const int lo[3], VoxelCorners& k)
{
  size_t off[3][2];
  size_t stride = 1;
  for (int a = 0; a < 3; ++a)
  {
    k.lo[a] = lo[a];
    off[a][0] = stride * static_cast<size_t>(std::clamp(lo[a], 0, dims[a] - 1));
    off[a][1] = stride * static_cast<size_t>(std::clamp(lo[a] + 1, 0, dims[a] - 1));
    stride *= static_cast<size_t>(dims[a]);
  }
  for (int c = 0; c < 8; ++c)
    k.idx[c] = index[off[0][c & 1] + off[1][(c >> 1) & 1] + off[2][(c >> 2) & 1]];
  k.uniform = std::all_of(k.idx + 1, k.idx + 8, [&](uint16_t i) { return i == k.idx[0]; });
  if (weights && !k.uniform) // a uniform cell's weights never matter
    for (int c = 0; c < 8; ++c)
      k.w[c] = weights[off[0][c & 1] + off[1][(c >> 1) & 1] + off[2][(c >> 2) & 1]];
  k.slotted = false;
}

/// Fills k's distinct labels and slots (a mixed cell's; loadCorners leaves them).
inline void distinctLabels(VoxelCorners& k)
{
  if (k.slotted || k.uniform)
    return;
  k.slotted = true;
  k.distinctCount = 0;
  for (int c = 0; c < 8; ++c)
  {
    int s = 0;
    while (s < k.distinctCount && k.distinct[s] != k.idx[c])
      ++s;
    if (s == k.distinctCount)
      k.distinct[k.distinctCount++] = k.idx[c];
    k.slot[c] = static_cast<uint8_t>(s);
  }
}

/// Summed trilinear weight of each distinct label of k at fractions f (sums in corner order).
inline void labelWeights(const VoxelCorners& k, const double f[3], double sums[8])
{
  const double g[3] = { 1.0 - f[0], 1.0 - f[1], 1.0 - f[2] };
  for (int s = 0; s < 8; ++s) // all 8, not distinctCount: a fixed size needs no memset call
    sums[s] = 0.0;
  for (int c = 0; c < 8; ++c)
    sums[k.slot[c]] += ((((c & 1) ? f[0] : g[0]) * ((c & 2) ? f[1] : g[1])) * ((c & 4) ? f[2] : g[2])) * k.w[c];
}

/// Compact label index with the largest of a mixed cell's summed weights; ties go to the smaller index.
inline uint16_t pickFromSums(const VoxelCorners& k, const double sums[8])
{
  uint16_t best = k.distinct[0];
  double bestWeight = sums[0];
  for (int s = 1; s < k.distinctCount; ++s)
    if (sums[s] > bestWeight || (sums[s] == bestWeight && k.distinct[s] < best))
    {
      best = k.distinct[s];
      bestWeight = sums[s];
    }
  return best;
}

/// Compact label index with the largest summed trilinear weight; ties go to the smaller index.
inline uint16_t pickLabel(const VoxelCorners& k, const double f[3])
{
  if (k.uniform)
    return k.idx[0]; // inside one label: the common case
  double sums[8];
  labelWeights(k, f, sums);
  return pickFromSums(k, sums);
}

/// The summed trilinear weight of `label` and the largest of the other labels' (a mixed cell's).
inline void ownAndStrongestOther(const VoxelCorners& k, const double sums[8], uint16_t label, double& own, double& other)
{
  own = 0.0;
  other = 0.0;
  for (int s = 0; s < k.distinctCount; ++s)
    if (k.distinct[s] == label)
      own = sums[s];
    else
      other = std::max(other, sums[s]);
}

/// How far `label` leads the strongest other label (a mixed cell's summed trilinear weights):
/// positive where it wins. The label change along a piece is a root of this piecewise cubic.
inline double leadFromSums(const VoxelCorners& k, const double sums[8], uint16_t label)
{
  double own, other;
  ownAndStrongestOther(k, sums, label, own, other);
  return own - other;
}
}
