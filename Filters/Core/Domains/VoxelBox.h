// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include "WorkerThreads.h"

#include <algorithm>
#include <array>
#include <cstddef>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

// The box of voxels around one label that the label map's smoothing works in, and passes over its
// lines and voxels in parallel.
namespace omesh
{
/// Scratch for one line of a box (one per thread): three value buffers with room for padding, and
/// the distance transform's envelope.
struct LineScratch
{
  explicit LineScratch(int n)
    : a(n + 64)
    , b(n + 64)
    , c(n + 64)
    , z(n + 1)
    , v(n)
  {
  }
  std::vector<double> a, b, c, z; ///< c: runningMaximum's third buffer
  std::vector<int> v;
};

/// A box of voxels [lo, hi) and its dense arrays' strides.
struct VoxelBox
{
  std::array<int, 3> lo{}, hi{};
  std::array<int, 3> n{};
  std::array<size_t, 3> stride{};
  size_t size = 0;

  void finish()
  {
    for (int a = 0; a < 3; ++a)
      n[a] = hi[a] - lo[a];
    stride = { 1, static_cast<size_t>(n[0]), static_cast<size_t>(n[0]) * n[1] };
    size = stride[2] * n[2];
  }
  bool contains(const int p[3]) const
  {
    return p[0] >= lo[0] && p[0] < hi[0] && p[1] >= lo[1] && p[1] < hi[1] && p[2] >= lo[2] && p[2] < hi[2];
  }
  size_t offset(const int p[3]) const
  {
    return static_cast<size_t>(p[0] - lo[0]) + stride[1] * (p[1] - lo[1]) + stride[2] * (p[2] - lo[2]);
  }
  /// The box-local coordinates of the voxel at `offset` (of its dense arrays).
  void coordinates(size_t offset, int p[3]) const
  {
    p[0] = static_cast<int>(offset % static_cast<size_t>(n[0]));
    p[1] = static_cast<int>((offset / static_cast<size_t>(n[0])) % static_cast<size_t>(n[1]));
    p[2] = static_cast<int>(offset / stride[2]);
  }
  int longest() const { return std::max({ n[0], n[1], n[2] }); }
};

/// Calls fn(line start, stride, length, scratch) for every line of `box` along `axis`, the lines
/// shared among threads (TBB), each thread with its own scratch.
template <class Fn>
void forEachLine(const VoxelBox& box, int axis, Fn&& fn)
{
  // neighbouring lines one after the other along x where the lines do not run along x: they read
  // the same cache lines (one line at a time across x re-read them from memory for each line)
  const int inner = axis == 0 ? 1 : 0, outer = 3 - axis - inner;
  tbb::parallel_for(tbb::blocked_range<int>(0, box.n[outer]), [&](const tbb::blocked_range<int>& rows) {
    LineScratch scratch(box.longest());
    for (int j = rows.begin(); j < rows.end(); ++j)
      for (int i = 0; i < box.n[inner]; ++i)
        fn(box.stride[inner] * i + box.stride[outer] * j, box.stride[axis], box.n[axis], scratch);
  });
}

/// Calls fn(i) for every i in [0, n), in chunks on the threads runOnThreads allows.
template <class Fn>
void forEachVoxel(size_t n, Fn&& fn)
{
  forEachChunk(n, chunkCount(n, 1 << 16), [&fn](size_t, size_t begin, size_t end) {
    for (size_t i = begin; i < end; ++i)
      fn(i);
  });
}

/// Running maximum of `values` over the cube of half-width r voxels (clamped at the box): per line,
/// van Herk and Gil-Werman's two running maxima in blocks of 2r + 1 (three comparisons a voxel
/// whatever r).
void runningMaximum(const VoxelBox& box, int r, std::vector<float>& values);
}
