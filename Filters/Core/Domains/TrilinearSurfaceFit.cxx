// SPDX-License-Identifier: GPL-3.0-or-later
#include "TrilinearSurfaceFit.h"

#include <algorithm>
#include <cmath>

namespace omesh
{
namespace
{
constexpr int kSamples = 4;                                   ///< per axis and cell
constexpr int kPerCell = kSamples * kSamples * kSamples;
constexpr double kWeightWidth = 0.5;                          ///< voxels: exp(-(d / this)^2)
constexpr double kHold = 1e-3;                                ///< pull towards the start, per unit of the diagonal
constexpr int kSweeps = 200;
constexpr double kSettled = 1e-5;                             ///< voxels: the largest change of a sweep

using CellSurface = std::function<std::function<double(const Vec3&)>(const std::vector<size_t>&)>;

/// A free voxel's equation: coefficients to the 27 voxels around it (index 9 (dz + 1) + 3 (dy + 1)
/// + dx + 1; the fixed ones already moved to the right-hand side), the right-hand side, its start.
struct Row
{
  std::array<double, 27> a{};
  double b = 0.0;
  float start = 0.0f;
};

class Fit
{
public:
  Fit(const VoxelBox& box, const std::array<double, 3>& h, std::vector<float>& psi, const std::vector<size_t>& free)
    : box_(box)
    , h_(h)
    , hMax_(std::max({ h[0], h[1], h[2] }))
    , psi_(psi)
    , free_(free)
    , rows_(free.size())
  {
    for (size_t i = 0; i < free.size(); ++i)
      rows_[i].start = psi[free[i]];
  }

  void assemble(const CellSurface& cellSurface)
  {
    for (size_t cell : cells())
      addCell(cell, cellSurface);
  }

  void solve(const std::vector<uint8_t>& inside, double delta)
  {
    for (int sweep = 0; sweep < kSweeps; ++sweep)
    {
      double change = 0.0;
      for (size_t i = 0; i < free_.size(); ++i)
      {
        const size_t v = free_[i];
        const Row& r = rows_[i];
        const double diagonal = r.a[13], hold = kHold * diagonal + 1e-30;
        if (!(diagonal > 0))
          continue;
        double sum = r.b + hold * r.start;
        for (int k = 0; k < 27; ++k)
          if (k != 13 && r.a[k] != 0.0)
            sum -= r.a[k] * psi_[neighbour(v, k)];
        double value = sum / (diagonal + hold);
        value = inside[v] ? std::max(value, delta) : std::min(value, -delta);
        change = std::max(change, std::abs(value - psi_[v]));
        psi_[v] = static_cast<float>(value);
      }
      if (change < kSettled * hMax_)
        break;
    }
  }

private:
  /// The voxel at neighbour index k of v (k's offset inside the box: the rows only hold those).
  size_t neighbour(size_t v, int k) const
  {
    const int dx = k % 3 - 1, dy = (k / 3) % 3 - 1, dz = k / 9 - 1;
    return v + static_cast<size_t>(static_cast<long long>(dx) + static_cast<long long>(dy) * static_cast<long long>(box_.stride[1]) +
                 static_cast<long long>(dz) * static_cast<long long>(box_.stride[2]));
  }
  /// The row of voxel v, or -1 when it is not free.
  long rowOf(size_t v) const
  {
    const auto it = std::lower_bound(free_.begin(), free_.end(), v);
    return it != free_.end() && *it == v ? static_cast<long>(it - free_.begin()) : -1;
  }

  /// The cells of voxel centres (by their lowest corner) with a free voxel among their corners.
  std::vector<size_t> cells() const
  {
    std::vector<size_t> out;
    for (size_t v : free_)
    {
      int p[3];
      box_.coordinates(v, p);
      for (int c = 0; c < 8; ++c)
      {
        const int q[3] = { p[0] - (c & 1), p[1] - ((c >> 1) & 1), p[2] - ((c >> 2) & 1) };
        if (q[0] >= 0 && q[1] >= 0 && q[2] >= 0 && q[0] + 1 < box_.n[0] && q[1] + 1 < box_.n[1] && q[2] + 1 < box_.n[2])
          out.push_back(static_cast<size_t>(q[0]) + box_.stride[1] * q[1] + box_.stride[2] * q[2]);
      }
    }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
  }

  /// One cell's least-squares terms: sum over its points of w (sum_c t_c psi_c - d)^2.
  void addCell(size_t cell, const CellSurface& cellSurface)
  {
    int lo[3];
    box_.coordinates(cell, lo);
    std::array<size_t, 8> corner;
    std::array<long, 8> row;
    std::vector<size_t> freeCorners;
    for (int c = 0; c < 8; ++c)
    {
      corner[c] = cell + (c & 1) + box_.stride[1] * ((c >> 1) & 1) + box_.stride[2] * ((c >> 2) & 1);
      row[c] = rowOf(corner[c]);
      if (row[c] >= 0)
        freeCorners.push_back(corner[c]);
    }
    const std::function<double(const Vec3&)> surfaceDistance = cellSurface(freeCorners);
    if (!surfaceDistance)
      return;
    double m[8][8] = {}, r[8] = {};
    for (int s = 0; s < kPerCell; ++s)
    {
      const double f[3] = { (s % kSamples + 0.5) / kSamples, ((s / kSamples) % kSamples + 0.5) / kSamples,
        (s / (kSamples * kSamples) + 0.5) / kSamples };
      double t[8];
      for (int c = 0; c < 8; ++c)
        t[c] = (c & 1 ? f[0] : 1 - f[0]) * (c & 2 ? f[1] : 1 - f[1]) * (c & 4 ? f[2] : 1 - f[2]);
      const Vec3 p{ (box_.lo[0] + lo[0] + f[0]) * h_[0], (box_.lo[1] + lo[1] + f[1]) * h_[1],
        (box_.lo[2] + lo[2] + f[2]) * h_[2] };
      const double d = surfaceDistance(p);
      if (!std::isfinite(d))
        continue;
      const double w = std::exp(-(d * d) / (kWeightWidth * kWeightWidth * hMax_ * hMax_)) / kPerCell;
      for (int a = 0; a < 8; ++a)
      {
        r[a] += w * t[a] * d;
        for (int b = 0; b < 8; ++b)
          m[a][b] += w * t[a] * t[b];
      }
    }
    for (int a = 0; a < 8; ++a)
    {
      if (row[a] < 0)
        continue;
      Row& eq = rows_[static_cast<size_t>(row[a])];
      eq.b += r[a];
      for (int b = 0; b < 8; ++b)
      {
        if (row[b] < 0)
        {
          eq.b -= m[a][b] * psi_[corner[b]];
          continue;
        }
        const int k = 9 * (((b >> 2) & 1) - ((a >> 2) & 1) + 1) + 3 * (((b >> 1) & 1) - ((a >> 1) & 1) + 1) + ((b & 1) - (a & 1) + 1);
        eq.a[k] += m[a][b];
      }
    }
  }

  const VoxelBox& box_;
  std::array<double, 3> h_;
  double hMax_;
  std::vector<float>& psi_;
  const std::vector<size_t>& free_;
  std::vector<Row> rows_;
};
}

void fitTrilinearToSurface(const VoxelBox& box, const std::array<double, 3>& h, std::vector<float>& psi,
  const std::vector<uint8_t>& inside, double delta, const std::vector<size_t>& free,
  const CellSurface& cellSurface)
{
  if (free.empty())
    return;
  Fit fit(box, h, psi, free);
  fit.assemble(cellSurface);
  fit.solve(inside, delta);
}
}
