// SPDX-License-Identifier: GPL-3.0-or-later
#include "LabelPlateauFit.h"

#include "SmallLinearSystem.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <functional>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace omesh
{
namespace
{
constexpr int kNoTop = INT_MIN; ///< a column without the label within the window's layers
constexpr int kFull = INT_MAX;  ///< a column of the label up to the window's top

/// The box seen along axis `a` from direction `s` (out of the label at a patch on layer `k`):
/// column (i, j) along the other two axes (b, c), m layers above layer k.
struct Frame
{
  const VoxelBox* box;
  int a, b, c, s, k;

  int columns(int axis) const { return box->n[axis == 0 ? b : c]; }
  bool has(int i, int j, int m) const
  {
    const int l = k + s * m;
    return i >= 0 && i < box->n[b] && j >= 0 && j < box->n[c] && l >= 0 && l < box->n[a];
  }
  size_t at(int i, int j, int m) const
  {
    return box->stride[a] * static_cast<size_t>(k + s * m) + box->stride[b] * static_cast<size_t>(i) +
      box->stride[c] * static_cast<size_t>(j);
  }
};

/// A step of the staircase: the surface passes `height` between two neighbouring columns, at
/// (u, v) within half a voxel along `along` (0: u, 1: v).
struct Wall
{
  double u, v, height, weight;
  int along;
};

/// A cap over a patch, in offsets from the patch's centre over `scale` (X, Y in-plane, Z the
/// height): Z = q(X, Y) + b Z^2 with q = c0 + c1 X + c2 Y + c3 X^2 + c4 X Y + c5 Y^2 and
/// b = (c3 + c5) / 2, a quadric surface with its axis along the grid's that curves along it as
/// much as across on average: a ball's cap exactly, down to its equator, and a bowl alike (two
/// rings of walls determine it). Linear in the coefficients, and a wall's height is exact: its
/// error is its sideways one through q.
class Cap
{
public:
  static constexpr int N = 6;

  Cap(double u0, double v0, double scale)
    : u0_(u0)
    , v0_(v0)
    , scale_(scale)
  {
  }

  /// The cap's height over (u, v) (world units); false where it has none (past its equator).
  bool height(double u, double v, double& z) const
  {
    const double q = quadric(u, v), b = bend();
    const double disc = 1.0 - 4.0 * b * q;
    if (!(disc >= 0.0))
      return false;
    z = scale_ * 2.0 * q / (1.0 + std::sqrt(disc)); // the root that tends to q as b does to 0
    return true;
  }

  /// dz/du and dz/dv at (u, v) on the cap at height z.
  std::array<double, 2> slope(double u, double v, double z) const
  {
    const auto g = quadricSlope(u, v);
    const double d = 1.0 - 2.0 * bend() * z / scale_;
    return { g[0] / d, g[1] / d };
  }

  /// Iteratively reweighted least squares: a wall's miss is its sideways error (uniform within
  /// half a voxel `side[along]`) times q's slope there, and `floor` (a length) for what the
  /// model misses. Returns the RMS of the walls' misses over their uncertainty, or a negative
  /// value when the walls do not determine a cap.
  double fit(const std::vector<Wall>& walls, const std::array<double, 2>& side, double floor)
  {
    double chi = -1.0;
    for (int round = 0; round < 4; ++round)
    {
      double m[N][N + 1] = {};
      double f[N];
      for (const Wall& w : walls)
      {
        const double weight = w.weight / (round == 0 ? 1.0 : variance(w, side, floor));
        basis(w, f);
        for (int i = 0; i < N; ++i)
        {
          for (int j = 0; j < N; ++j)
            m[i][j] += weight * f[i] * f[j];
          m[i][N] += weight * f[i] * w.height / scale_;
        }
      }
      for (int i = 1; i < N; ++i)
        m[i][i] += 1e-9 * m[0][0]; // directions the walls do not spread along stay level
      double c[N];
      if (!solveLinear<N>(m, c))
        return -1.0;
      std::copy(c, c + N, c_);
      double miss = 0.0, total = 0.0;
      for (const Wall& w : walls)
      {
        basis(w, f);
        double r = -w.height / scale_;
        for (int i = 0; i < N; ++i)
          r += c_[i] * f[i];
        miss += w.weight * r * r / variance(w, side, floor);
        total += w.weight;
      }
      chi = std::sqrt(miss / total);
    }
    return chi;
  }

private:
  double bend() const { return 0.5 * (c_[3] + c_[5]); }
  void basis(const Wall& w, double (&f)[N]) const
  {
    const double x = (w.u - u0_) / scale_, y = (w.v - v0_) / scale_, z = w.height / scale_;
    f[0] = 1.0;
    f[1] = x;
    f[2] = y;
    f[3] = x * x + 0.5 * z * z;
    f[4] = x * y;
    f[5] = y * y + 0.5 * z * z;
  }
  double quadric(double u, double v) const
  {
    const double x = (u - u0_) / scale_, y = (v - v0_) / scale_;
    return c_[0] + c_[1] * x + c_[2] * y + c_[3] * x * x + c_[4] * x * y + c_[5] * y * y;
  }
  /// dq/du and dq/dv (q in units of scale, u and v world).
  std::array<double, 2> quadricSlope(double u, double v) const
  {
    const double x = (u - u0_) / scale_, y = (v - v0_) / scale_;
    return { c_[1] + 2 * c_[3] * x + c_[4] * y, c_[2] + c_[4] * x + 2 * c_[5] * y };
  }
  /// A wall's variance in units of scale^2.
  double variance(const Wall& w, const std::array<double, 2>& side, double floor) const
  {
    const double g = quadricSlope(w.u, w.v)[w.along] * side[w.along] / scale_;
    return (g * g / 12.0 + floor * floor / (scale_ * scale_));
  }

  double u0_, v0_, scale_;
  double c_[N] = {};
};

/// A patch whose cap the walls agree on: its columns (i + n_b j), the cap, and whether the cap
/// sets its rim too (a hill's top or a pit's bottom; a terrace's rim may lie across an edge).
struct PatchCap
{
  Frame frame;
  std::vector<int> columns;
  Cap cap;
  bool rim;
};

class PlateauFinder
{
public:
  PlateauFinder(const VoxelBox& box, const std::array<double, 3>& h, const std::vector<uint8_t>& inside,
    const std::function<int(size_t)>& other, const LabelPlateauOptions& options)
    : box_(box)
    , h_(h)
    , inside_(inside)
    , other_(other)
    , options_(options)
  {
  }

  /// The caps of the patches on layer k seen along a from s.
  void findOnLayer(const Frame& f, std::vector<PatchCap>& out) const
  {
    const int nb = f.columns(0), nc = f.columns(1);
    std::vector<uint8_t> top(static_cast<size_t>(nb) * nc, 0);
    bool any = false;
    for (int j = 0; j < nc; ++j)
      for (int i = 0; i < nb; ++i)
      {
        top[i + nb * j] = inside_[f.at(i, j, 0)] && !inside_[f.at(i, j, 1)];
        any = any || top[i + nb * j];
      }
    if (!any)
      return;
    std::vector<int> stack, patch;
    for (int start = 0; start < nb * nc; ++start)
    {
      if (top[start] != 1)
        continue;
      patch.clear();
      stack.assign(1, start);
      top[start] = 2;
      int interior = 0, lowerAround = 0, higherAround = 0;
      while (!stack.empty())
      {
        const int cell = stack.back();
        stack.pop_back();
        patch.push_back(cell);
        const int i = cell % nb, j = cell / nb;
        const int next[4][2] = { { i - 1, j }, { i + 1, j }, { i, j - 1 }, { i, j + 1 } };
        int around = 0;
        for (const auto& q : next)
        {
          if (q[0] < 0 || q[0] >= nb || q[1] < 0 || q[1] >= nc)
            continue;
          if (!top[q[0] + nb * q[1]]) // a neighbouring column lower (no label on the patch's layer) or higher
          {
            const bool lower = !inside_[f.at(q[0], q[1], 0)];
            lowerAround += lower;
            higherAround += !lower;
            continue;
          }
          ++around;
          if (top[q[0] + nb * q[1]] == 1)
          {
            top[q[0] + nb * q[1]] = 2;
            stack.push_back(q[0] + nb * q[1]);
          }
        }
        interior += around == 4;
      }
      // a cap's patch is the top of a hill or the bottom of a pit: its neighbouring columns all
      // lower or all higher (a tilted plane's terraces have both, and the filters follow planes)
      const bool extremum = lowerAround == 0 || higherAround == 0;
      if (!extremum && interior < options_.minimumInterior)
        continue;
      // a cap lies between two labels: one label beyond the whole patch
      const int beyond = other_(f.at(patch[0] % nb, patch[0] / nb, 1));
      if (std::all_of(patch.begin(), patch.end(), [&](int c) { return other_(f.at(c % nb, c / nb, 1)) == beyond; }))
        fitPatch(f, patch, extremum, beyond, out);
    }
  }

private:
  /// The columns around a patch whose walls fit its cap: [i0, i1] x [j0, j1], each column's top
  /// (layers above the patch's; kNoTop, kFull: none within the window's layers, all of them), the
  /// patch's centre, how far its walls count and the width of their weights.
  struct Window
  {
    int i0, i1, j0, j1;
    double u0, v0, reach, width;
    std::vector<int> tops;
    int& top(int i, int j) { return tops[(i - i0) + (i1 - i0 + 1) * (j - j0)]; }
    int top(int i, int j) const { return tops[(i - i0) + (i1 - i0 + 1) * (j - j0)]; }
  };

  Window windowOf(const Frame& f, const std::vector<int>& patch) const
  {
    const int nb = f.columns(0), nc = f.columns(1);
    const double hb = h_[f.b], hc = h_[f.c], hMax = std::max({ h_[0], h_[1], h_[2] });
    int lo[2] = { INT_MAX, INT_MAX }, hi[2] = { INT_MIN, INT_MIN };
    double su = 0.0, sv = 0.0;
    for (int cell : patch)
    {
      const int i = cell % nb, j = cell / nb;
      lo[0] = std::min(lo[0], i);
      hi[0] = std::max(hi[0], i);
      lo[1] = std::min(lo[1], j);
      hi[1] = std::max(hi[1], j);
      su += i * hb;
      sv += j * hc;
    }
    Window w;
    w.u0 = su / patch.size();
    w.v0 = sv / patch.size();
    const double radius = 0.5 * std::max((hi[0] - lo[0] + 1) * hb, (hi[1] - lo[1] + 1) * hc);
    const double margin = options_.margin * hMax; // the coarsest axis: a CT slice's rings lie far apart
    w.reach = radius + margin;
    w.width = radius + 0.5 * margin;
    w.i0 = std::max(0, lo[0] - static_cast<int>(std::ceil(margin / hb)) - 1);
    w.i1 = std::min(nb - 1, hi[0] + static_cast<int>(std::ceil(margin / hb)) + 1);
    w.j0 = std::max(0, lo[1] - static_cast<int>(std::ceil(margin / hc)) - 1);
    w.j1 = std::min(nc - 1, hi[1] + static_cast<int>(std::ceil(margin / hc)) + 1);
    w.tops.resize(static_cast<size_t>(w.i1 - w.i0 + 1) * (w.j1 - w.j0 + 1));
    // a column's top: where the label's run through the patch's layer ends above it, or, where the
    // column is outside on that layer, the highest layer of the label below it (seen from the
    // patch, so a part of the label beyond the other one's, past the window, does not count)
    const int highest = options_.layers + 1;
    for (int j = w.j0; j <= w.j1; ++j)
      for (int i = w.i0; i <= w.i1; ++i)
      {
        int t = kNoTop;
        if (inside_[f.at(i, j, 0)])
        {
          t = 0;
          while (t < highest && f.has(i, j, t + 1) && inside_[f.at(i, j, t + 1)])
            ++t;
          if (t == highest)
            t = kFull;
        }
        else
          for (int m = -1; m >= -options_.layers && t == kNoTop; --m)
            if (f.has(i, j, m) && inside_[f.at(i, j, m)])
              t = m;
        w.top(i, j) = t;
      }
    return w;
  }

  /// The walls between the window's neighbouring columns, between the label and `beyond`.
  std::vector<Wall> wallsOf(const Frame& f, const Window& w, int beyond) const
  {
    const double hb = h_[f.b], hc = h_[f.c], ha = h_[f.a];
    std::vector<Wall> walls;
    for (int j = w.j0; j <= w.j1; ++j)
      for (int i = w.i0; i <= w.i1; ++i)
        for (int along = 0; along < 2; ++along)
        {
          const int i2 = i + (along == 0), j2 = j + (along == 1);
          if (i2 > w.i1 || j2 > w.j1)
            continue;
          const int t1 = w.top(i, j), t2 = w.top(i2, j2);
          // a column without the label in the window lies below every layer of its neighbour's
          // top run (a cap's steep sides down to its equator); a column of the label up to the
          // window's top lies above every layer above its neighbour's top (a pit's sides)
          if (t1 == t2 || ((t1 == kNoTop || t1 == kFull) && (t2 == kNoTop || t2 == kFull)))
            continue;
          const double u = (along == 0 ? i + 0.5 : i) * hb, v = (along == 1 ? j + 0.5 : j) * hc;
          const double d = std::hypot(u - w.u0, v - w.v0);
          if (d > w.reach)
            continue;
          const bool firstHigher = t1 > t2;
          const int hiCol[2] = { firstHigher ? i : i2, firstHigher ? j : j2 };
          const int loCol[2] = { firstHigher ? i2 : i, firstHigher ? j2 : j };
          const int low = std::min(t1, t2) == kNoTop ? -options_.layers - 1 : std::min(t1, t2);
          const int high = std::max(t1, t2) == kFull ? options_.layers + 1 : std::max(t1, t2);
          for (int m = high; m > low; --m)
          {
            if (!f.has(hiCol[0], hiCol[1], m) || !inside_[f.at(hiCol[0], hiCol[1], m)])
            {
              if (std::min(t1, t2) == kNoTop)
                break; // the top run ends
              continue;
            }
            if (other_(f.at(loCol[0], loCol[1], m)) == beyond) // not where a third label meets the two
              walls.push_back({ u, v, m * ha, std::exp(-(d / w.width) * (d / w.width)), along });
          }
        }
    return walls;
  }

  /// The cap over one patch, appended to `out` when the walls agree on it.
  void fitPatch(const Frame& f, const std::vector<int>& patch, bool extremum, int beyond, std::vector<PatchCap>& out) const
  {
    const int nb = f.columns(0);
    const double hb = h_[f.b], hc = h_[f.c], ha = h_[f.a];
    const Window w = windowOf(f, patch);
    const std::vector<Wall> walls = wallsOf(f, w, beyond);
    const auto [lowest, tallest] = std::minmax_element(
      walls.begin(), walls.end(), [](const Wall& a, const Wall& b) { return a.height < b.height; });
    if (walls.size() < 12 || !(tallest->height > lowest->height)) // two layers of walls at least
      return;
    Cap cap(w.u0, w.v0, w.width);
    const double chi = cap.fit(walls, { hb, hc }, 0.03 * std::min({ ha, hb, hc }));
    if (!(chi >= 0.0 && chi <= options_.consistency))
      return;
    for (int cell : patch)
    {
      const double u = (cell % nb) * hb, v = (cell / nb) * hc;
      double z;
      if (!cap.height(u, v, z))
        return;
      const auto g = cap.slope(u, v, z);
      if (!(z >= -0.25 * ha && z <= 1.25 * ha) || std::hypot(g[0], g[1]) > options_.maximumSlope)
        return;
    }
    out.push_back({ f, patch, cap, extremum });
  }

  const VoxelBox& box_;
  const std::array<double, 3>& h_;
  const std::vector<uint8_t>& inside_;
  const std::function<int(size_t)>& other_;
  const LabelPlateauOptions& options_;
};

/// psi over the patch's columns and their rim, on the patch's layer, the one below and the two
/// above: the distance to the cap along its normal, on each voxel's side of zero.
void applyCap(const PatchCap& p, const std::array<double, 3>& h, const std::vector<uint8_t>& inside, double delta,
  std::vector<float>& psi)
{
  const Frame& f = p.frame;
  const int nb = f.columns(0);
  std::vector<int> columns = p.columns;
  if (p.rim)
    for (int cell : p.columns)
    {
      const int i = cell % nb, j = cell / nb;
      const int next[4][2] = { { i - 1, j }, { i + 1, j }, { i, j - 1 }, { i, j + 1 } };
      for (const auto& q : next)
        if (f.has(q[0], q[1], 0))
          columns.push_back(q[0] + nb * q[1]);
    }
  std::sort(columns.begin(), columns.end());
  columns.erase(std::unique(columns.begin(), columns.end()), columns.end());
  for (int cell : columns)
  {
    const double u = (cell % nb) * h[f.b], v = (cell / nb) * h[f.c];
    double z;
    if (!p.cap.height(u, v, z))
      continue;
    const auto g = p.cap.slope(u, v, z);
    const double across = 1.0 / std::sqrt(1.0 + g[0] * g[0] + g[1] * g[1]);
    for (int m = -1; m <= 2; ++m)
    {
      if (!f.has(cell % nb, cell / nb, m))
        continue;
      const size_t o = f.at(cell % nb, cell / nb, m);
      const double d = (z - m * h[f.a]) * across;
      psi[o] = static_cast<float>(inside[o] ? std::max(d, delta) : std::min(d, -delta));
    }
  }
}
}

void fitLabelPlateaus(const VoxelBox& box, const std::array<double, 3>& h, std::vector<float>& psi,
  const std::vector<uint8_t>& inside, const std::function<int(size_t)>& other, double delta,
  const LabelPlateauOptions& options)
{
  const PlateauFinder finder(box, h, inside, other, options);
  for (int a = 0; a < 3; ++a)
    for (int s : { 1, -1 })
    {
      // the layers' caps found in parallel (they read the labels only), set in layer order
      // (neighbouring layers' rims overlap)
      std::vector<std::vector<PatchCap>> caps(static_cast<size_t>(box.n[a]));
      tbb::parallel_for(tbb::blocked_range<int>(0, box.n[a]), [&](const tbb::blocked_range<int>& layers) {
        for (int k = layers.begin(); k < layers.end(); ++k)
          if (k + s >= 0 && k + s < box.n[a])
            finder.findOnLayer({ &box, a, (a + 1) % 3, (a + 2) % 3, s, k }, caps[k]);
      });
      for (const std::vector<PatchCap>& layer : caps)
        for (const PatchCap& p : layer)
          applyCap(p, h, inside, delta, psi);
    }
}
}
