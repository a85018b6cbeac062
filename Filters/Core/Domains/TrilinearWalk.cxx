// SPDX-License-Identifier: GPL-3.0-or-later
#include "TrilinearWalk.h"

#include "TrilinearCubic.h"

#include <cmath>

namespace omesh
{
bool TrilinearWalk::leadOnPiece(double a, double b, const int cell[3], uint16_t label, double lead[4])
{
  if (!sameCell(cell, cache_.lo))
    loadCorners(dims_, index_, weights_, cell, cache_);
  const VoxelCorners& k = cache_;
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

uint16_t TrilinearWalk::labelAtStart(double t, double t1, bool& noChange)
{
  int lo[3];
  uint16_t label = 0;
  const int c = clearanceAt(t, lo, label);
  noChange = c > 0 && exitOfCube(lo, c) >= t1;
  return c > 0 ? label : labelAt(t);
}

double TrilinearWalk::lastOf(uint16_t label, double lo, double hi)
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

double TrilinearWalk::leadAt(double t, uint16_t label, uint16_t& at)
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

double TrilinearWalk::interpolated(double lo, double hi, double gLo, double gHi, int side, double fallback)
{
  const double tol = 1e-12 * (1.0 + std::abs(hi));
  double x = lo + (hi - lo) * gLo / (gLo - gHi) + 0.5 * tol * (side == -1 ? 1.0 : side == 1 ? -1.0 : 0.0);
  if (gLo == 0.0)
    x = lo + 0.5 * tol;
  else if (gHi == 0.0)
    x = hi - 0.5 * tol;
  return x > lo && x < hi ? x : fallback;
}
}
