// SPDX-License-Identifier: GPL-3.0-or-later
#include "LabelMapDomain.h"

#include "InputError.h"

#include <algorithm>
#include <cmath>
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
  for (int i = 0; i < 3; ++i)
  {
    if (d[i] == 0.0)
    {
      if (!(ua[i] >= 0.0 && ua[i] <= dimsD_[i]))
        return;
      continue;
    }
    double ta = (0.0 - ua[i]) / d[i], tb = (dimsD_[i] - ua[i]) / d[i];
    if (ta > tb)
      std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
  if (!(t0 <= t1))
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

void LabelMapDomain::gather(const Vec3& u, uint16_t idx[8], double w[8]) const
{
  // the 8 voxel centres (i + 0.5) around u, clamped at the grid's border
  int lo[3];
  double f[3];
  for (int a = 0; a < 3; ++a)
  {
    const double x = u[a] - 0.5;
    const double fl = std::floor(x);
    lo[a] = static_cast<int>(fl);
    f[a] = x - fl;
  }
  for (int c = 0; c < 8; ++c)
  {
    size_t offset = 0, stride = 1;
    double weight = 1.0;
    for (int a = 0; a < 3; ++a)
    {
      const int up = (c >> a) & 1;
      const int i = std::clamp(lo[a] + up, 0, dims_[a] - 1);
      offset += stride * static_cast<size_t>(i);
      stride *= static_cast<size_t>(dims_[a]);
      weight *= up ? f[a] : 1.0 - f[a];
    }
    idx[c] = index_[offset];
    w[c] = weight;
  }
}

uint16_t LabelMapDomain::trilinearIndex(const Vec3& u) const
{
  uint16_t idx[8];
  double w[8];
  gather(u, idx, w);
  if (std::all_of(idx + 1, idx + 8, [&](uint16_t i) { return i == idx[0]; }))
    return idx[0]; // inside one label: the common case
  // largest summed weight; ties go to the smaller index (deterministic)
  uint16_t best = idx[0];
  double bestWeight = -1.0;
  for (int c = 0; c < 8; ++c)
  {
    bool seen = false;
    for (int k = 0; k < c && !seen; ++k)
      seen = idx[k] == idx[c];
    if (seen)
      continue;
    double sum = 0.0;
    for (int k = c; k < 8; ++k)
      sum += idx[k] == idx[c] ? w[k] : 0.0;
    if (sum > bestWeight || (sum == bestWeight && idx[c] < best))
    {
      best = idx[c];
      bestWeight = sum;
    }
  }
  return best;
}

void LabelMapDomain::trilinearCrossings(
  const Vec3& ua, const Vec3& d, double t0, double t1, std::vector<double>& ts) const
{
  // Between the planes through voxel centres the indicators are trilinear (cubic along the
  // segment): sample each such piece four times and bisect every change of label to full
  // precision. Two changes closer than a quarter of a piece may be missed (a sliver of a label
  // thinner than about a quarter voxel along the segment).
  std::vector<double> planes{ t0, t1 };
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
  auto labelAt = [&](double t) {
    const Vec3 u = ua + t * d;
    return trilinearIndex(clampToGrid(u));
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
      uint16_t idx[8];
      double w[8];
      gather(clampToGrid(um), idx, w);
      if (std::all_of(idx, idx + 8, [&](uint16_t i) { return i == previous; }))
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
