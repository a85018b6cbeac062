// SPDX-License-Identifier: GPL-3.0-or-later
#include "LabelPieces.h"

#include "UnionFind.h"
#include "WorkerThreads.h"

#include <algorithm>

namespace omesh
{
LabelPieces::LabelPieces(const std::array<int, 3>& dims, const std::vector<uint16_t>& index)
  : dims_(dims)
{
  const size_t rows = static_cast<size_t>(dims[1]) * dims[2];
  // the runs of each slab of rows in parallel, then one after the other
  const size_t slabs = chunkCount(rows, 64);
  std::vector<std::vector<int>> slabX(slabs);
  std::vector<std::vector<uint16_t>> slabLabel(slabs);
  std::vector<std::vector<uint32_t>> slabRuns(slabs); // runs per row of the slab
  forEachChunk(rows, slabs, [&](size_t slab, size_t begin, size_t end) {
    for (size_t row = begin; row < end; ++row)
    {
      const uint16_t* line = index.data() + row * dims[0];
      uint32_t n = 0;
      for (int x = 0; x < dims[0]; ++x)
        if (x == 0 || line[x] != line[x - 1])
        {
          slabX[slab].push_back(x);
          slabLabel[slab].push_back(line[x]);
          ++n;
        }
      slabRuns[slab].push_back(n);
    }
  });
  std::vector<uint16_t> runLabel;
  rowFirst_.reserve(rows + 1);
  for (size_t slab = 0; slab < slabs; ++slab)
  {
    size_t at = 0;
    for (uint32_t n : slabRuns[slab])
    {
      rowFirst_.push_back(static_cast<uint32_t>(runX_.size()));
      runX_.insert(runX_.end(), slabX[slab].begin() + at, slabX[slab].begin() + at + n);
      runLabel.insert(runLabel.end(), slabLabel[slab].begin() + at, slabLabel[slab].begin() + at + n);
      at += n;
    }
    std::vector<int>().swap(slabX[slab]);
    std::vector<uint16_t>().swap(slabLabel[slab]);
  }
  rowFirst_.push_back(static_cast<uint32_t>(runX_.size()));
  auto runEnd = [&](size_t row, uint32_t r) { return r + 1 < rowFirst_[row + 1] ? runX_[r + 1] : dims_[0]; };
  // runs of one label that overlap along x in neighbouring rows (y - 1, or z - 1) are one piece
  UnionFind sets(runX_.size());
  for (size_t row = 0; row < rows; ++row)
  {
    const size_t y = row % dims[1];
    for (const size_t below : { y > 0 ? row - 1 : rows, row >= static_cast<size_t>(dims[1]) ? row - dims[1] : rows })
    {
      if (below == rows)
        continue;
      uint32_t a = rowFirst_[row], b = rowFirst_[below];
      while (a < rowFirst_[row + 1] && b < rowFirst_[below + 1])
      {
        if (runLabel[a] == runLabel[b] && runX_[a] < runEnd(below, b) && runX_[b] < runEnd(row, a))
          sets.join(a, b);
        if (runEnd(row, a) < runEnd(below, b))
          ++a;
        else
          ++b;
      }
    }
  }
  runPiece_.resize(runX_.size());
  std::vector<uint32_t> pieceOfRoot(runX_.size(), UINT32_MAX);
  for (size_t row = 0; row < rows; ++row)
    for (uint32_t r = rowFirst_[row]; r < rowFirst_[row + 1]; ++r)
    {
      uint32_t& piece = pieceOfRoot[sets.find(r)];
      if (piece == UINT32_MAX)
      {
        piece = static_cast<uint32_t>(label_.size());
        label_.push_back(runLabel[r]);
        voxels_.push_back(0);
      }
      runPiece_[r] = piece;
      voxels_[piece] += static_cast<size_t>(runEnd(row, r) - runX_[r]);
    }
}

uint32_t LabelPieces::at(size_t v) const
{
  const size_t row = v / dims_[0];
  const int x = static_cast<int>(v % dims_[0]);
  const auto first = runX_.begin() + rowFirst_[row], last = runX_.begin() + rowFirst_[row + 1];
  return runPiece_[static_cast<size_t>(std::upper_bound(first, last, x) - runX_.begin()) - 1];
}

void LabelPieces::fill(const VoxelBox& box, uint32_t piece, std::vector<uint8_t>& inside) const
{
  inside.assign(box.size, 0);
  forEachVoxel(static_cast<size_t>(box.n[1]) * box.n[2], [&](size_t line) {
    const int y = static_cast<int>(line % box.n[1]), z = static_cast<int>(line / box.n[1]);
    const size_t row = static_cast<size_t>(box.lo[1] + y) + static_cast<size_t>(dims_[1]) * (box.lo[2] + z);
    uint8_t* out = inside.data() + box.stride[1] * y + box.stride[2] * z;
    for (uint32_t r = rowFirst_[row]; r < rowFirst_[row + 1]; ++r)
    {
      if (runPiece_[r] != piece)
        continue;
      const int end = r + 1 < rowFirst_[row + 1] ? runX_[r + 1] : dims_[0];
      for (int x = std::max(runX_[r], box.lo[0]); x < std::min(end, box.hi[0]); ++x)
        out[x - box.lo[0]] = 1;
    }
  });
}
}
