// SPDX-License-Identifier: GPL-3.0-or-later
#include "LabelMapDomain.h"

#include "BoundingBox.h"

#include "InputError.h"
#include "LabelSmoothing.h"
#include "TrilinearCubic.h"
#include "TrilinearWalk.h"
#include "VoxelCorners.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>

namespace omesh
{
namespace
{
/// floor(x) and ceil(x) of a voxel coordinate (|x| far below 2^31), as doubles, the same values as
/// std::floor and std::ceil (up to the sign of a zero) without their rounding sequences (the piece
/// ends' setup per query would cost ~1.5 % of a coarse label map's refinement): truncation, then a step
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

uint16_t LabelMapDomain::trilinearIndex(const Vec3& u) const
{
  int lo[3];
  double f[3];
  splitCell(u, lo, f);
  if (clearance_[clearanceOffset(clearanceStride_, lo)] != 0)
    return index_[lowerCorner(dims_, lo)]; // all 8 corners carry one label
  VoxelCorners k;
  loadCorners(dims_, index_.data(), weights_.empty() ? nullptr : weights_.data(), lo, k);
  distinctLabels(k);
  return pickLabel(k, f);
}

namespace
{
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

/// Samples per piece where the lead's cubic does not decide (LabelMapDomain::trilinearCrossings).
constexpr int kSamples = 4;
/// How far beyond rounding the lead's cubic must be from 0 to decide (the cubic's coefficients and
/// the trilinear evaluation differ by a few 1e-14 in voxel grids of ~1000 voxels).
constexpr double kMargin = 1e-10;

/// The lead's cubic on the piece [a, b] of a mixed cell (lo): a certificate that `previous` holds,
/// or in a cell of two labels every change along the piece (added to `found`), without samples;
/// `previous` and `previousT` are then left as the samples would leave them. False when the cubic
/// cannot decide: the piece is to be sampled.
bool leadCrossings(TrilinearWalk& walk, double a, double b, const int lo[3], uint16_t& previous, double& previousT,
  WalkCrossings& found)
{
  double lead[4], roots[3];
  const bool two = walk.leadOnPiece(a, b, lo, previous, lead);
  const int n = trilinear::allAbove(lead, kMargin) ? 0
    : two && lead[0] > 0.0                        ? trilinear::signChanges(lead, a, b, kMargin, roots)
                                                  : -1;
  if (n < 0)
    return false;
  uint16_t other = n > 0 ? walk.otherLabel() : previous;
  for (int r = 0; r < n; ++r)
  {
    found.add(roots[r], previous, other);
    std::swap(previous, other);
  }
  previousT = a + (b - a) * kSamples / kSamples; // the last sample's t, as the samples leave it
  return true;
}
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
  double previousT = t0;
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
    // a mixed cell: the lead's cubic decides where it can; elsewhere, and where it cannot, samples
    if (clearance != 0 || !leadCrossings(walk, a, b, lo, previous, previousT, found))
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
