// SPDX-License-Identifier: GPL-3.0-or-later
#include "LabelMapDomain.h"

#include "BoundingBox.h"

#include "InputError.h"
#include "LabelSmoothing.h"
#include "TrilinearCubic.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>

namespace omesh
{
namespace
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

/// floor(x) and ceil(x) of a voxel coordinate (|x| far below 2^31), as doubles, the same values as
/// std::floor and std::ceil (up to the sign of a zero) without their rounding sequences (the piece
/// ends' setup per query was ~1.5 % of a coarse label map's refinement): truncation, then a step
/// towards the rounding direction where it went the other way.
inline double floorOf(double x)
{
  const int i = static_cast<int>(x);
  return static_cast<double>(i > x ? i - 1 : i);
}
inline double ceilOf(double x)
{
  const int i = static_cast<int>(x);
  return static_cast<double>(i < x ? i + 1 : i);
}

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
  const AffineMap& worldToVoxel, int backgroundLabel, const std::string& name, LabelInterpolation interpolation,
  const LabelSmoothingOptions& smoothing)
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
  if (interpolation_ == LabelInterpolation::Nearest)
    return;
  buildClearance();
  if (interpolation_ == LabelInterpolation::Smooth)
  {
    std::array<double, 3> spacing{}; // the voxel axes' lengths in world units
    for (int c = 0; c < 3; ++c)
      spacing[c] = std::sqrt(r[c] * r[c] + r[4 + c] * r[4 + c] + r[8 + c] * r[8 + c]);
    weights_ = labelInterfaceWeights(dims_, index_, static_cast<int>(indexMaterial_.size()), spacing, smoothing);
  }
}

void LabelMapDomain::buildClearance()
{
  // cells 0 .. dims per axis at 1 .. dims + 1; the padding never is mixed and never changes
  const std::array<size_t, 3> n{ static_cast<size_t>(dims_[0]) + 3, static_cast<size_t>(dims_[1]) + 3,
    static_cast<size_t>(dims_[2]) + 3 };
  clearanceStride_ = { 1, n[0], n[0] * n[1] };
  clearance_.assign(n[0] * n[1] * n[2], 255);
  const size_t row = static_cast<size_t>(dims_[0]), slice = row * static_cast<size_t>(dims_[1]);
  auto cells = [&](size_t y, size_t z) { return clearance_.data() + n[0] * (y + n[1] * z); }; // padded row
  // Mixed cells: their 8 corners (voxels x - 1 and x of rows y - 1, y of slices z - 1, z, clamped)
  // differ. Rows of corners first: equal[x] says voxels x - 1 and x of the 4 rows are one label.
  std::vector<uint8_t> equal(static_cast<size_t>(dims_[0]) + 1);
  for (int z = 0; z <= dims_[2]; ++z)
  {
    const size_t z0 = slice * std::max(z - 1, 0), z1 = slice * std::min(z, dims_[2] - 1);
    for (int y = 0; y <= dims_[1]; ++y)
    {
      const size_t y0 = row * std::max(y - 1, 0), y1 = row * std::min(y, dims_[1] - 1);
      const uint16_t* r[4] = { index_.data() + z0 + y0, index_.data() + z0 + y1, index_.data() + z1 + y0,
        index_.data() + z1 + y1 };
      // per voxel column x: whether the 4 rows agree there
      for (int x = 0; x < dims_[0]; ++x)
        equal[x] = r[0][x] == r[1][x] && r[0][x] == r[2][x] && r[0][x] == r[3][x];
      uint8_t* out = cells(static_cast<size_t>(y) + 1, static_cast<size_t>(z) + 1) + 1;
      out[0] = equal[0] ? 255 : 0;
      for (int x = 1; x < dims_[0]; ++x)
        out[x] = equal[x - 1] && equal[x] && r[0][x - 1] == r[0][x] ? 255 : 0;
      out[dims_[0]] = equal[dims_[0] - 1] ? 255 : 0;
    }
  }
  // Chebyshev distance: a forward and a backward pass over the 26-neighbourhood with unit steps
  // (exact for this metric). Per row, the 12 neighbours in rows done before, then along the row.
  std::vector<uint8_t> done(n[0]);
  // dir 1: rows y - 1 of slice z and y - 1 .. y + 1 of slice z - 1 are done; dir -1: the mirror
  auto pass = [&](size_t y, size_t z, ptrdiff_t dir) {
    const size_t yb = y - dir, ya = y + dir, zb = z - dir; // before, after (modular for dir = -1)
    const uint8_t* rows[4] = { cells(yb, zb), cells(y, zb), cells(ya, zb), cells(yb, z) };
    for (size_t x = 1; x + 1 < n[0]; ++x)
    {
      uint8_t m = 255;
      for (const uint8_t* q : rows)
        m = std::min({ m, q[x - 1], q[x], q[x + 1] });
      done[x] = m;
    }
    uint8_t* c = cells(y, z);
    for (size_t i = 0, x = dir > 0 ? 1 : n[0] - 2; i + 2 < n[0]; ++i, x += dir)
      if (c[x] != 0)
        c[x] = static_cast<uint8_t>(std::min({ static_cast<int>(c[x]), done[x] + 1, c[x - dir] + 1 }));
  };
  for (size_t z = 1; z + 1 < n[2]; ++z)
    for (size_t y = 1; y + 1 < n[1]; ++y)
      pass(y, z, 1);
  for (size_t z = n[2] - 2; z >= 1; --z)
    for (size_t y = n[1] - 2; y >= 1; --y)
      pass(y, z, -1);
}

bool LabelMapDomain::firstChange(const Vec3& a, const Vec3& b, ShownChange& shown, std::vector<double>& ts,
  bool& candidatesShown) const
{
  if (interpolation_ == LabelInterpolation::Nearest)
  {
    candidatesShown = firstCrossings(a, b, ts, 1);
    return false;
  }
  const Vec3 ua = worldToVoxel_.apply(a), ub = worldToVoxel_.apply(b), d = ub - ua;
  auto inGrid = [&](const Vec3& u) {
    return u.x >= 0.0 && u.y >= 0.0 && u.z >= 0.0 && u.x <= dimsD_[0] && u.y <= dimsD_[1] && u.z <= dimsD_[2];
  };
  double t0 = 0.0, t1 = 1.0;
  if (!inGrid(ua) || !inGrid(ub)) // (both ends in the grid: the clip keeps 0 and 1)
  {
    if (!isFinite(ua) || !isFinite(d))
    {
      candidatesShown = firstCrossings(a, b, ts, 1);
      return false;
    }
    BoundingBox grid;
    grid.add(Vec3{ 0.0, 0.0, 0.0 });
    grid.add(Vec3{ dimsD_[0], dimsD_[1], dimsD_[2] });
    if (!grid.clip(ua, d, t0, t1)) // outside the grid all along
      return true;
    if (!(t0 < t1)) // touches the grid's boundary only: the oracle looks
    {
      candidatesShown = firstCrossings(a, b, ts, 1);
      return false;
    }
  }
  // as firstCrossings: the walk on [t0, t1] after the candidates t0 and t1
  const size_t from = ts.size();
  ts.push_back(t0);
  ts.push_back(t1);
  WalkReport walk;
  candidatesShown = trilinearCrossings(ua, d, t0, t1, 1, ts, &walk) && t0 == 0.0 && t1 == 1.0;
  if (walk.sampled)
    return false;
  // No piece sampled up to the first change: the walk's start label is the material at t0 (the
  // same evaluation as material() there), its first change is exact and the label after it holds
  // up to the next change or the piece's end; outside the grid every point is outside. These are
  // the answers of the oracle's checks at the candidates' midpoints.
  const int start = indexMaterial_[walk.start];
  auto change = [&](double t, int after) {
    shown.found = true;
    shown.t = t;
    shown.after = after;
    return true;
  };
  shown.before = t0 > 0.0 ? kOutside : start;
  if (start != shown.before) // a outside the grid, material where ab enters it
    return change(t0, start);
  if (ts.size() > from + 2)
    return change(ts[from + 2], indexMaterial_[walk.afterFirst]);
  const int end = indexMaterial_[walk.afterFirst]; // no change: the last label
  if (t1 < 1.0 && end != kOutside)                 // b outside the grid
    return change(t1, kOutside);
  return true;
}

bool LabelMapDomain::firstCrossings(const Vec3& a, const Vec3& b, std::vector<double>& ts, int changes) const
{
  const Vec3 ua = worldToVoxel_.apply(a), ub = worldToVoxel_.apply(b), d = ub - ua;
  if (!isFinite(ua) || !isFinite(d)) // a NaN end is outside every domain: nothing to cross
    return false;
  // Clip to the grid [0, dims] (slab method); entering and leaving the grid are candidates.
  double t0 = 0.0, t1 = 1.0;
  BoundingBox grid;
  grid.add(Vec3{ 0.0, 0.0, 0.0 });
  grid.add(Vec3{ dimsD_[0], dimsD_[1], dimsD_[2] });
  if (!grid.clip(ua, d, t0, t1))
    return false;
  ts.push_back(t0);
  ts.push_back(t1);
  if (interpolation_ != LabelInterpolation::Nearest)
    return trilinearCrossings(ua, d, t0, t1, changes, ts) && t0 == 0.0 && t1 == 1.0; // both ends in the grid
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
  return false;
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
  const std::array<int, 3>& dims, const uint16_t* index, const float* weights, const int lo[3], Corners& k)
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
inline void distinctLabels(Corners& k)
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
inline void labelWeights(const Corners& k, const double f[3], double sums[8])
{
  const double g[3] = { 1.0 - f[0], 1.0 - f[1], 1.0 - f[2] };
  for (int s = 0; s < 8; ++s) // all 8, not distinctCount: a fixed size needs no memset call
    sums[s] = 0.0;
  for (int c = 0; c < 8; ++c)
    sums[k.slot[c]] += ((((c & 1) ? f[0] : g[0]) * ((c & 2) ? f[1] : g[1])) * ((c & 4) ? f[2] : g[2])) * k.w[c];
}

/// Compact label index with the largest of a mixed cell's summed weights; ties go to the smaller index.
inline uint16_t pickFromSums(const Corners& k, const double sums[8])
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
inline uint16_t pickLabel(const Corners& k, const double f[3])
{
  if (k.uniform)
    return k.idx[0]; // inside one label: the common case
  double sums[8];
  labelWeights(k, f, sums);
  return pickFromSums(k, sums);
}

/// How far `label` leads the strongest other label (a mixed cell's summed trilinear weights):
/// positive where it wins. The label change along a piece is a root of this piecewise cubic.
inline double leadFromSums(const Corners& k, const double sums[8], uint16_t label)
{
  double own = 0.0, other = 0.0;
  for (int s = 0; s < k.distinctCount; ++s)
    if (k.distinct[s] == label)
      own = sums[s];
    else
      other = std::max(other, sums[s]);
  return own - other;
}
}

uint16_t LabelMapDomain::trilinearIndex(const Vec3& u) const
{
  int lo[3];
  double f[3];
  splitCell(u, lo, f);
  if (clearance_[clearanceOffset(clearanceStride_, lo)] != 0)
    return index_[lowerCorner(dims_, lo)]; // all 8 corners carry one label
  Corners k;
  loadCorners(dims_, index_.data(), weights_.empty() ? nullptr : weights_.data(), lo, k);
  distinctLabels(k);
  return pickLabel(k, f);
}

namespace
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
  bool leadOnPiece(double a, double b, const int cell[3], uint16_t label, double lead[4])
  {
    if (!sameCell(cell, cache_.lo))
      loadCorners(dims_, index_, weights_, cell, cache_);
    const Corners& k = cache_;
    double fa[3], fb[3]; // (in a cell at the grid's border the clamped corners repeat along the
    for (int end = 0; end < 2; ++end) // outer axis: the fractions there do not matter)
    {
      const Vec3 u = ua_ + (end == 0 ? a : b) * d_;
      double* fe = end == 0 ? fa : fb;
      for (int ax = 0; ax < 3; ++ax)
        fe[ax] = std::clamp(u[ax] - 0.5 - k.lo[ax], 0.0, 1.0);
    }
    // the corners' values, and whether the cell's labels are `label` and one other (the first
    // corner of another label's), from the corners alone (no list of distinct labels)
    double v[8];
    bool has = false, two = true;
    other_ = label;
    for (int c = 0; c < 8; ++c)
    {
      const uint16_t i = k.idx[c];
      const bool own = i == label;
      v[c] = own ? k.w[c] : -k.w[c];
      has = has || own;
      if (!own && other_ == label)
        other_ = i;
      two = two && (own || i == other_);
    }
    trilinear::bernsteinOnLine(v, fa, fb, lead);
    return has && two && other_ != label;
  }

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
  uint16_t labelAtStart(double t, double t1, bool& noChange)
  {
    int lo[3];
    uint16_t label = 0;
    const int c = clearanceAt(t, lo, label);
    noChange = c > 0 && exitOfCube(lo, c) >= t1;
    return c > 0 ? label : labelAt(t);
  }

  /// The last t where `label` holds between lo (it holds) and hi (it does not), to 1e-12: a
  /// bracketing search (Illinois regula falsi on the label's lead, a bisection whenever three
  /// steps do not halve the bracket) that keeps the bisection's answer to its tolerance with about
  /// a fifth of its label evaluations.
  double lastOf(uint16_t label, double lo, double hi)
  {
    uint16_t at = 0;
    double gLo = leadAt(lo, label, at), gHi = leadAt(hi, label, at);
    int side = 0;               // which end the last step moved: -1 lo, +1 hi
    double reference = hi - lo; // a bisection once 3 steps have not halved the bracket from here
    int steps = 0;
    while (hi - lo > 1e-12 * (1.0 + std::abs(hi)))
    {
      const double w = hi - lo;
      if (w <= 0.5 * reference)
      {
        reference = w;
        steps = 0;
      }
      double mid = 0.5 * (lo + hi);
      if (++steps <= 3 && gLo >= 0.0 && gHi <= 0.0)
        mid = interpolated(lo, hi, gLo, gHi, side, mid);
      else
      {
        reference = w;
        steps = 0;
      }
      const double g = leadAt(mid, label, at);
      const bool holds = at == label;
      (holds ? lo : hi) = mid;
      (holds ? gLo : gHi) = g;
      if (side == (holds ? -1 : 1))
        (holds ? gHi : gLo) *= 0.5; // Illinois: the end that stayed twice counts half
      side = holds ? -1 : 1;
    }
    return hi;
  }

private:
  /// The label at t and how far `label` leads there.
  double leadAt(double t, uint16_t label, uint16_t& at)
  {
    double f[3];
    cornersAt(t, f);
    if (cache_.uniform)
    {
      at = cache_.idx[0];
      return at == label ? 1.0 : -1.0;
    }
    double sums[8]; // one set of weights for both answers
    labelWeights(cache_, f, sums);
    at = pickFromSums(cache_, sums);
    return leadFromSums(cache_, sums, label);
  }

  /// A little past the interpolated root, away from the end that moved last: once the root is
  /// known to the tolerance, that closes the bracket in one step. A lead of exactly 0 is a tie
  /// decided by index: the change is most likely right at that end. `fallback` if outside.
  static double interpolated(double lo, double hi, double gLo, double gHi, int side, double fallback)
  {
    const double tol = 1e-12 * (1.0 + std::abs(hi));
    double x = lo + (hi - lo) * gLo / (gLo - gHi) + 0.5 * tol * (side == -1 ? 1.0 : side == 1 ? -1.0 : 0.0);
    if (gLo == 0.0)
      x = lo + 0.5 * tol;
    else if (gHi == 0.0)
      x = hi - 0.5 * tol;
    return x > lo && x < hi ? x : fallback;
  }

  const std::array<int, 3>& dims_;
  const uint16_t* index_;
  const float* weights_; ///< interface weights per voxel (Smooth), or null
  const uint8_t* clearance_;
  const std::array<size_t, 3>& clearanceStride_;
  Vec3 ua_, d_;
  Corners cache_;
  uint16_t other_ = 0; ///< leadOnPiece's other label
};

/// The ends of a walk's pieces in increasing order: t0, t1 and every t in between where ua + t d
/// crosses a plane through voxel centres (u = k + 0.5), merged from the three axes' arithmetic
/// sequences (the same values a sorted list of them holds).
class PieceEnds
{
public:
  PieceEnds(const Vec3& ua, const Vec3& d, double t0, double t1)
    : ua_(ua)
    , d_(d)
    , ends_{ t0, t1 }
  {
    for (int i = 0; i < 3; ++i)
    {
      if (d[i] == 0.0)
        continue;
      // the planes k + 0.5 with lo < k < hi
      const double lo = std::min(ua[i] + t0 * d[i], ua[i] + t1 * d[i]) - 0.5;
      const double hi = std::max(ua[i] + t0 * d[i], ua[i] + t1 * d[i]) - 0.5;
      const double first = floorOf(lo) + 1.0, last = ceilOf(hi) - 1.0;
      if (!(first <= last))
        continue;
      left_[i] = static_cast<long>(last - first) + 1;
      k_[i] = d[i] > 0.0 ? first : last;
      step_[i] = d[i] > 0.0 ? 1.0 : -1.0;
      next_[i] = plane(i);
      remaining_ += left_[i];
    }
  }

  /// The next end; false when there is none left.
  bool next(double& t)
  {
    if (remaining_ == 0)
      return false;
    --remaining_;
    int from = -1;
    t = nextEnd_ < 2 ? ends_[nextEnd_] : std::numeric_limits<double>::infinity();
    for (int i = 0; i < 3; ++i)
      if (left_[i] != 0 && next_[i] < t)
      {
        t = next_[i];
        from = i;
      }
    if (from < 0)
      ++nextEnd_;
    else
      advance(from);
    return true;
  }

  /// Takes every end up to tExit; returns the largest of them and `last`.
  double skipThrough(double tExit, double last)
  {
    for (int i = 0; i < 3; ++i)
      while (left_[i] != 0 && next_[i] <= tExit)
      {
        last = std::max(last, next_[i]);
        --remaining_;
        advance(i);
      }
    while (nextEnd_ < 2 && ends_[nextEnd_] <= tExit)
    {
      last = std::max(last, ends_[nextEnd_++]);
      --remaining_;
    }
    return last;
  }

private:
  double plane(int i) const { return (k_[i] + 0.5 - ua_[i]) / d_[i]; }
  void advance(int i)
  {
    if (--left_[i] != 0)
    {
      k_[i] += step_[i];
      next_[i] = plane(i);
    }
  }

  Vec3 ua_, d_;
  double ends_[2];
  int nextEnd_ = 0;
  long remaining_ = 2;
  long left_[3] = { 0, 0, 0 };
  double k_[3] = {}, step_[3] = {}, next_[3] = {};
};

/// The crossings a walk appends after the first `from` entries of ts, with the label before each.
struct WalkCrossings
{
  std::vector<double>& ts;
  size_t from;
  std::vector<uint16_t>& labelsBefore;

  void add(double t, uint16_t before, uint16_t after)
  {
    if (ts.size() > from && t - ts.back() <= 1e-12 * (1.0 + std::abs(t)))
    {
      // Two changes within the tolerance: the label flickers where two labels tie along the
      // segment (rounding decides). They are one change, or none if it comes back.
      const uint16_t origin = labelsBefore.back();
      ts.pop_back();
      labelsBefore.pop_back();
      if (origin != after)
      {
        ts.push_back(t);
        labelsBefore.push_back(origin);
      }
      return;
    }
    ts.push_back(t);
    labelsBefore.push_back(before);
  }
};
}

bool LabelMapDomain::trilinearCrossings(const Vec3& ua, const Vec3& d, double t0, double t1, int changes,
  std::vector<double>& ts, WalkReport* report) const
{
  // Between the planes through voxel centres the indicators are trilinear (cubic along the
  // segment). In a cell of two labels (most mixed cells) the walk's label holds where its lead
  // over the other, one cubic, is positive: the cubic's Bernstein coefficients show that it holds
  // on the piece, or its critical points split the piece into monotone parts and every sign
  // change is found by Newton steps (TrilinearCubic.h), however thin the layer. Elsewhere, and
  // where rounding could decide (the lead within 1e-10 of 0 at a piece's end or at a critical
  // point: a change at a plane through voxel centres, a tangency), the piece is sampled four
  // times and every change between samples is searched to full precision; two changes closer
  // than a quarter of such a piece may be missed.
  // Most pieces lie in a cell whose 8 corners all carry the label the walk is in (one load of
  // clearance_ says so; nothing can change there), most of those deep inside a cube of such
  // cells, which the walk jumps over to the plane where it leaves the cube.
  TrilinearWalk walk(dims_, index_.data(), weights_.empty() ? nullptr : weights_.data(), clearance_.data(),
    clearanceStride_, ua, d);
  bool noChange = false;
  uint16_t previous = walk.labelAtStart(t0, t1, noChange);
  if (report)
    report->start = report->afterFirst = previous;
  if (noChange) // the whole segment in one cube of one label: the walk would jump to its end
    return true;
  thread_local std::vector<uint16_t> labelsBefore; // reused: no allocation per query
  labelsBefore.clear();
  WalkCrossings found{ ts, ts.size(), labelsBefore };
  PieceEnds ends(ua, d, t0, t1);
  constexpr int kSamples = 4;
  double previousT = t0;
  // how far beyond rounding the lead's cubic must be from 0 to decide (the cubic's coefficients and
  // the trilinear evaluation differ by a few 1e-14 in voxel grids of ~1000 voxels)
  constexpr double kMargin = 1e-10;
  bool sampled = false; // a piece's label was sampled, not shown (returns false)
  // Samples the piece [pa, pb] four times and searches every change of label between samples.
  auto sampleAndSearch = [&](double pa, double pb) {
    sampled = true;
    for (int s = 1; s <= kSamples; ++s)
    {
      const double t = pa + (pb - pa) * s / kSamples;
      const uint16_t at = walk.labelAt(t);
      // every change between the previous sample and t (a few at most)
      for (int guard = 0; at != previous && guard < 8; ++guard)
      {
        const double hi = walk.lastOf(previous, previousT, t);
        const uint16_t after = walk.labelAt(hi);
        found.add(hi, previous, after);
        previous = after;
        previousT = hi;
      }
      previous = at;
      previousT = t;
    }
  };
  double a = 0.0, b = 0.0;
  ends.next(a);
  for (; ends.next(b); a = b)
  {
    if (!(b > a))
      continue;
    int lo[3];
    uint16_t label = 0;
    const int clearance = walk.clearanceAt(0.5 * (a + b), lo, label);
    if (clearance > 0 && label == previous)
    {
      if (clearance > 1) // the pieces up to the cube's exit lie in cells of this label too
        b = ends.skipThrough(walk.exitOfCube(lo, clearance), b);
      previousT = b;
      continue;
    }
    if (clearance == 0)
    {
      // the lead's cubic: a certificate that the label holds, or in a cell of two labels every
      // change along the piece, without samples
      double lead[4], roots[3];
      const bool two = walk.leadOnPiece(a, b, lo, previous, lead);
      const int n = trilinear::allAbove(lead, kMargin) ? 0
        : two && lead[0] > 0.0                        ? trilinear::signChanges(lead, a, b, kMargin, roots)
                                                      : -1;
      if (n >= 0)
      {
        uint16_t other = n > 0 ? walk.otherLabel() : previous;
        for (int r = 0; r < n; ++r)
        {
          found.add(roots[r], previous, other);
          std::swap(previous, other);
        }
        previousT = a + (b - a) * kSamples / kSamples; // the last sample's t, as the samples leave it
      }
      else
        sampleAndSearch(a, b);
    }
    else
      sampleAndSearch(a, b);
    // enough changes: the rest of the walk cannot come before them. The piece's end is a
    // candidate too: the material after the last change holds up to it (or the samples would
    // have found another change), so the caller can tell it from the material before.
    if (ts.size() - found.from >= static_cast<size_t>(changes))
    {
      ts.push_back(b);
      break;
    }
  }
  if (report)
  {
    report->sampled = sampled;
    // the label before the second change, or the last one
    report->afterFirst = labelsBefore.size() > 1 ? labelsBefore[1] : previous;
  }
  return !sampled && ts.size() == found.from;
}

void LabelMapDomain::bendPlanes(const Vec3& a, const Vec3& b, std::vector<BendPlane>& planes) const
{
  const Vec3 ua = worldToVoxel_.apply(a), ub = worldToVoxel_.apply(b);
  // trilinear: the interpolation cells between voxel centres (at i + 0.5) meet there
  const double offset = interpolation_ != LabelInterpolation::Nearest ? 0.5 : 0.0;
  const auto& m = worldToVoxel_.rows();
  for (int axis = 0; axis < 3; ++axis)
  {
    const double lo = std::min(ua[axis], ub[axis]), hi = std::max(ua[axis], ub[axis]);
    const double first = std::floor(lo - offset) + 1.0 + offset; // the first plane above lo
    for (double c = first; c < hi && c <= dimsD_[axis]; c += 1.0)
    {
      const double t = (c - ua[axis]) / (ub[axis] - ua[axis]);
      // the gradient of voxel coordinate `axis` in world space: row `axis` of the linear part
      planes.push_back({ lerp(a, b, t), Vec3{ m[4 * axis], m[4 * axis + 1], m[4 * axis + 2] } });
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
