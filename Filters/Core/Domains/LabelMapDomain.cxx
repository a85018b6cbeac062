// SPDX-License-Identifier: GPL-3.0-or-later
#include "LabelMapDomain.h"

#include "BoundingBox.h"

#include "InputError.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>

namespace omesh
{
namespace
{
AffineMap voxelToWorld(const Vec3& origin, const Vec3& spacing, const std::array<double, 9>& d, double shift)
{
  // world = origin + D * diag(spacing) * (u + shift)
  std::array<double, 12> m{};
  for (int r = 0; r < 3; ++r)
  {
    double t = origin[r];
    for (int c = 0; c < 3; ++c)
    {
      m[4 * r + c] = d[3 * r + c] * spacing[c];
      t += d[3 * r + c] * spacing[c] * shift;
    }
    m[4 * r + 3] = t;
  }
  return AffineMap(m);
}
}

AffineMap LabelMapDomain::pointCenteredWorldToVoxel(
  const Vec3& origin, const Vec3& spacing, const std::array<double, 9>& direction)
{
  return voxelToWorld(origin, spacing, direction, -0.5).inverse();
}

AffineMap LabelMapDomain::cellCenteredWorldToVoxel(
  const Vec3& origin, const Vec3& spacing, const std::array<double, 9>& direction)
{
  return voxelToWorld(origin, spacing, direction, 0.0).inverse();
}

LabelMapDomain::LabelMapDomain(const std::array<int, 3>& dims, const std::vector<int>& labels,
  const AffineMap& worldToVoxel, int backgroundLabel, const std::string& name, LabelInterpolation interpolation)
  : dims_(dims)
  , worldToVoxel_(worldToVoxel)
  , interpolation_(interpolation)
{
  setName(name);
  if (dims[0] <= 0 || dims[1] <= 0 || dims[2] <= 0)
    throw InputError(name + ": label map is empty (" + std::to_string(dims[0]) + " x " +
      std::to_string(dims[1]) + " x " + std::to_string(dims[2]) + " voxels)");
  // the product in double first: three ints can multiply past 2^64, and a product that wrapped to
  // the number of labels given would pass the size check below
  const double voxels = static_cast<double>(dims[0]) * dims[1] * dims[2];
  if (voxels > 1e15)
    throw InputError(name + ": label map has " + std::to_string(dims[0]) + " x " + std::to_string(dims[1]) + " x " +
      std::to_string(dims[2]) + " voxels, beyond any memory");
  const size_t n = static_cast<size_t>(dims[0]) * dims[1] * dims[2];
  if (labels.size() != n)
    throw InputError(name + ": label map has " + std::to_string(labels.size()) + " labels for " +
      std::to_string(n) + " voxels");
  for (int i = 0; i < 3; ++i)
    dimsD_[i] = dims[i];
  AffineMap toWorld;
  try
  {
    toWorld = worldToVoxel.inverse(); // throws if singular or not finite
  }
  catch (const InputError& e)
  {
    throw InputError(name + ": label map placement (origin, spacing, direction): " + e.what());
  }
  const auto& r = toWorld.rows();
  voxelVolume_ = std::abs(r[0] * (r[5] * r[10] - r[6] * r[9]) - r[1] * (r[4] * r[10] - r[6] * r[8]) +
    r[2] * (r[4] * r[9] - r[5] * r[8]));

  std::unordered_map<int, uint16_t> compact;
  compact[backgroundLabel] = 0;
  indexMaterial_.push_back(kOutside);
  index_.resize(n);
  for (size_t v = 0; v < n; ++v)
  {
    const int label = labels[v];
    auto it = compact.find(label);
    if (it == compact.end())
    {
      if (label < 0)
        throw InputError(name + ": label " + std::to_string(label) + " (voxel " + std::to_string(v) +
          ") is negative; labels other than the background must be >= 0");
      if (indexMaterial_.size() > 65535)
        throw InputError(name + ": label map has more than 65535 distinct labels");
      it = compact.emplace(label, static_cast<uint16_t>(indexMaterial_.size())).first;
      indexMaterial_.push_back(label);
    }
    index_[v] = it->second;
  }
}

void LabelMapDomain::crossings(const Vec3& a, const Vec3& b, std::vector<double>& ts) const
{
  const Vec3 ua = worldToVoxel_.apply(a), ub = worldToVoxel_.apply(b), d = ub - ua;
  if (!isFinite(ua) || !isFinite(d)) // a NaN end is outside every domain: nothing to cross
    return;
  // Clip to the grid [0, dims] (slab method); entering and leaving the grid are candidates.
  double t0 = 0.0, t1 = 1.0;
  BoundingBox grid;
  grid.add(Vec3{ 0.0, 0.0, 0.0 });
  grid.add(Vec3{ dimsD_[0], dimsD_[1], dimsD_[2] });
  if (!grid.clip(ua, d, t0, t1))
    return;
  ts.push_back(t0);
  ts.push_back(t1);
  if (interpolation_ == LabelInterpolation::Trilinear)
  {
    trilinearCrossings(ua, d, t0, t1, ts);
    return;
  }
  // Voxel faces crossed inside the grid; keep those where the label actually changes.
  std::vector<double> faces{ t0 };
  for (int i = 0; i < 3; ++i)
  {
    if (d[i] == 0.0)
      continue;
    const double lo = std::min(ua[i] + t0 * d[i], ua[i] + t1 * d[i]);
    const double hi = std::max(ua[i] + t0 * d[i], ua[i] + t1 * d[i]);
    for (double k = std::floor(lo) + 1.0; k < hi; k += 1.0)
      faces.push_back((k - ua[i]) / d[i]);
  }
  faces.push_back(t1);
  std::sort(faces.begin(), faces.end());
  int previous = -2;
  for (size_t f = 0; f + 1 < faces.size(); ++f)
  {
    if (faces[f + 1] <= faces[f])
      continue;
    const double tm = 0.5 * (faces[f] + faces[f + 1]);
    const Vec3 um = ua + tm * d;
    const Vec3 uc = clampToGrid(um);
    const int label = index_[voxelOf(uc)];
    if (previous != -2 && label != previous)
      ts.push_back(faces[f]);
    previous = label;
  }
}

namespace
{
/// The 8 voxel centres around a point: lower corner `lo` (may lie outside the grid; indices are
/// clamped at the border) and their compact label indices. Within one cell of voxel centres they
/// do not change, so a walk along a segment loads them once per cell.
struct Corners
{
  int lo[3] = { std::numeric_limits<int>::min(), 0, 0 };
  uint16_t idx[8] = {};
  bool uniform = false;
};

/// Lower voxel-centre corner and fractions of u (continuous voxel coordinates).
inline void splitCell(const Vec3& u, int lo[3], double f[3])
{
  for (int a = 0; a < 3; ++a)
  {
    const double x = u[a] - 0.5;
    const double fl = std::floor(x);
    lo[a] = static_cast<int>(fl);
    f[a] = x - fl;
  }
}

inline bool sameCell(const int a[3], const int b[3]) { return a[0] == b[0] && a[1] == b[1] && a[2] == b[2]; }

inline void loadCorners(const std::array<int, 3>& dims, const uint16_t* index, const int lo[3], Corners& k)
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
}

/// Compact label index with the largest summed trilinear weight; ties go to the smaller index.
inline uint16_t pickLabel(const Corners& k, const double f[3])
{
  if (k.uniform)
    return k.idx[0]; // inside one label: the common case
  double w[8];
  for (int c = 0; c < 8; ++c)
  {
    double weight = 1.0;
    for (int a = 0; a < 3; ++a)
      weight *= ((c >> a) & 1) ? f[a] : 1.0 - f[a];
    w[c] = weight;
  }
  const uint16_t* idx = k.idx;
  uint16_t best = idx[0];
  double bestWeight = -1.0;
  for (int c = 0; c < 8; ++c)
  {
    bool seen = false;
    for (int j = 0; j < c && !seen; ++j)
      seen = idx[j] == idx[c];
    if (seen)
      continue;
    double sum = 0.0;
    for (int j = c; j < 8; ++j)
      sum += idx[j] == idx[c] ? w[j] : 0.0;
    if (sum > bestWeight || (sum == bestWeight && idx[c] < best))
    {
      best = idx[c];
      bestWeight = sum;
    }
  }
  return best;
}
}

uint16_t LabelMapDomain::trilinearIndex(const Vec3& u) const
{
  int lo[3];
  double f[3];
  splitCell(u, lo, f);
  Corners k;
  loadCorners(dims_, index_.data(), lo, k);
  return pickLabel(k, f);
}

void LabelMapDomain::trilinearCrossings(
  const Vec3& ua, const Vec3& d, double t0, double t1, std::vector<double>& ts) const
{
  // Between the planes through voxel centres the indicators are trilinear (cubic along the
  // segment): sample each such piece four times and bisect every change of label to full
  // precision. Two changes closer than a quarter of a piece may be missed (a sliver of a label
  // thinner than about a quarter voxel along the segment).
  thread_local std::vector<double> planes; // reused: no allocation per query
  planes.clear();
  planes.push_back(t0);
  planes.push_back(t1);
  for (int i = 0; i < 3; ++i)
  {
    if (d[i] == 0.0)
      continue;
    const double lo = std::min(ua[i] + t0 * d[i], ua[i] + t1 * d[i]) - 0.5;
    const double hi = std::max(ua[i] + t0 * d[i], ua[i] + t1 * d[i]) - 0.5;
    for (double k = std::floor(lo) + 1.0; k < hi; k += 1.0)
      planes.push_back((k + 0.5 - ua[i]) / d[i]);
  }
  std::sort(planes.begin(), planes.end());
  // The 8 labels around the last point looked at: the samples and the bisection inside one piece
  // only recompute the weights (the answers are those of trilinearIndex at every point).
  Corners cache;
  auto labelAt = [&](double t) {
    const Vec3 u = clampToGrid(ua + t * d);
    int lo[3];
    double f[3];
    splitCell(u, lo, f);
    if (!sameCell(lo, cache.lo))
      loadCorners(dims_, index_.data(), lo, cache);
    return pickLabel(cache, f);
  };
  constexpr int kSamples = 4;
  double previousT = t0;
  uint16_t previous = labelAt(t0);
  for (size_t p = 0; p + 1 < planes.size(); ++p)
  {
    const double a = planes[p], b = planes[p + 1];
    if (!(b > a))
      continue;
    {
      // a piece whose 8 voxel centres all carry the label we are in cannot change it
      const Vec3 um = ua + (0.5 * (a + b)) * d;
      int lo[3];
      double f[3];
      splitCell(clampToGrid(um), lo, f);
      if (!sameCell(lo, cache.lo))
        loadCorners(dims_, index_.data(), lo, cache);
      if (cache.uniform && cache.idx[0] == previous)
      {
        previousT = b;
        continue;
      }
    }
    for (int s = 1; s <= kSamples; ++s)
    {
      const double t = a + (b - a) * s / kSamples;
      const uint16_t label = labelAt(t);
      // every change between the previous sample and t (a few at most)
      for (int guard = 0; label != previous && guard < 8; ++guard)
      {
        double lo = previousT, hi = t;
        while (hi - lo > 1e-12 * (1.0 + std::abs(hi)))
        {
          const double mid = 0.5 * (lo + hi);
          (labelAt(mid) == previous ? lo : hi) = mid;
        }
        ts.push_back(hi);
        previous = labelAt(hi);
        previousT = hi;
      }
      previous = label;
      previousT = t;
    }
  }
}

BoundingBox LabelMapDomain::bounds() const
{
  BoundingBox grid;
  grid.add({ 0, 0, 0 });
  grid.add({ dimsD_[0], dimsD_[1], dimsD_[2] });
  return worldToVoxel_.inverseImageOf(grid);
}

std::vector<int> LabelMapDomain::materials() const
{
  std::vector<int> m(indexMaterial_.begin() + 1, indexMaterial_.end());
  std::sort(m.begin(), m.end());
  return m;
}

std::map<int, size_t> LabelMapDomain::voxelCounts() const
{
  std::vector<size_t> perIndex(indexMaterial_.size(), 0);
  for (uint16_t i : index_)
    ++perIndex[i];
  std::map<int, size_t> counts;
  for (size_t i = 1; i < perIndex.size(); ++i)
    counts[indexMaterial_[i]] = perIndex[i];
  return counts;
}
}
