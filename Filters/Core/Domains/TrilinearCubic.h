// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Along a straight line inside one cell of voxel centres, a trilinear function of the cell's 8
// corner values is a cubic polynomial in the line's parameter. The label map's walk
// (LabelMapDomain::trilinearCrossings) decides with these where the label of a cell of two
// labels changes along a piece of a segment, and where a label holds on a piece, without
// sampling it: the cubic's Bernstein coefficients bound it (a certificate that it keeps its
// sign), its critical points (a quadratic, in closed form) split it into monotone parts with at
// most one root each, and a root is found by Newton steps kept inside a bracket.

#include <algorithm>
#include <cmath>

namespace omesh::trilinear
{
/// Bernstein coefficients b (on x in [0, 1]) of the trilinear interpolant of the corner values v
/// (corner c at fractions (c & 1, (c >> 1) & 1, (c >> 2) & 1)) along the straight line from the
/// fractions fa (x = 0) to fb (x = 1). The interpolant is affine in each fraction and each fraction
/// is affine in x, so coefficient k is the mean of the interpolant at the corners of the line's
/// bounding box with k of the 3 fractions taken from fb and the others from fa (the polar form).
inline void bernsteinOnLine(const double v[8], const double fa[3], const double fb[3], double b[4])
{
  double ex[4][2]; // x collapsed at both ends, per (y, z) corner pair
  for (int q = 0; q < 4; ++q)
  {
    const double dv = v[2 * q + 1] - v[2 * q];
    ex[q][0] = v[2 * q] + dv * fa[0];
    ex[q][1] = v[2 * q] + dv * fb[0];
  }
  double box[2][2][2]; // [x from fb][y from fb][z from fb]
  for (int sx = 0; sx < 2; ++sx)
    for (int sy = 0; sy < 2; ++sy)
    {
      const double y = sy ? fb[1] : fa[1];
      const double z0 = ex[0][sx] + (ex[1][sx] - ex[0][sx]) * y, z1 = ex[2][sx] + (ex[3][sx] - ex[2][sx]) * y;
      box[sx][sy][0] = z0 + (z1 - z0) * fa[2];
      box[sx][sy][1] = z0 + (z1 - z0) * fb[2];
    }
  constexpr double third = 1.0 / 3.0;
  b[0] = box[0][0][0];
  b[1] = (box[1][0][0] + box[0][1][0] + box[0][0][1]) * third;
  b[2] = (box[0][1][1] + box[1][0][1] + box[1][1][0]) * third;
  b[3] = box[1][1][1];
}

/// Whether every Bernstein coefficient exceeds `margin`: then the cubic exceeds it on all of [0, 1]
/// (it is a convex combination of them).
inline bool allAbove(const double b[4], double margin)
{
  return b[0] > margin && b[1] > margin && b[2] > margin && b[3] > margin;
}

/// The cubic's coefficients in the power basis (p(x) = c[0] + c[1] x + c[2] x^2 + c[3] x^3).
inline void powerFromBernstein(const double b[4], double c[4])
{
  c[0] = b[0];
  c[1] = 3.0 * (b[1] - b[0]);
  c[2] = 3.0 * (b[0] - 2.0 * b[1] + b[2]);
  c[3] = b[3] - b[0] + 3.0 * (b[1] - b[2]);
}

inline double evalPower(const double c[4], double x) { return ((c[3] * x + c[2]) * x + c[1]) * x + c[0]; }

/// Whether the Bernstein coefficients change sign exactly once, even where one within `margin` of 0
/// took the sign that makes the most changes: with b[0] and b[3] of opposite signs (beyond the
/// margin), the cubic then has exactly one root in (0, 1) (Descartes' rule of signs in the
/// Bernstein basis: the roots are at most the sign changes, and of the same parity).
inline bool oneSignChange(const double b[4], double margin)
{
  // the most sign changes up to coefficient i, ending in + (best[0]) or in - (best[1])
  constexpr int none = -100;
  int plus = b[0] > 0.0 ? 0 : none, minus = b[0] < 0.0 ? 0 : none;
  for (int i = 1; i < 4; ++i)
  {
    const bool canPlus = b[i] > -margin, canMinus = b[i] < margin;
    const int p = canPlus ? std::max(plus, minus + 1) : none;
    const int m = canMinus ? std::max(minus, plus + 1) : none;
    plus = p;
    minus = m;
  }
  return std::max(plus, minus) == 1;
}

/// The first t of [lo, hi] where p((t - ta) * scale) no longer has the sign `s` (+1 or -1) it has
/// at lo, to 1e-12 (1 + |t|) as the label map's search: p has sign s at lo and -s (or 0) at hi and
/// one root between. Newton steps kept inside the bracket: where a step leaves it, the secant
/// between the bracket's ends, and a bisection where the bracket has not halved in three steps
/// and the step is not small against it.
/// Once a step is below the tolerance, a point just past it on the other side closes the bracket.
inline double lastOfSign(const double c[4], double ta, double scale, double s, double lo, double hi)
{
  double vLo = s * evalPower(c, (lo - ta) * scale), vHi = s * evalPower(c, (hi - ta) * scale);
  auto secant = [&]() {
    const double x = vLo - vHi > 0.0 ? lo + (hi - lo) * (vLo / (vLo - vHi)) : 0.5 * (lo + hi);
    return x > lo && x < hi ? x : 0.5 * (lo + hi);
  };
  double t = secant();
  double reference = hi - lo;
  int steps = 0;
  for (int guard = 0; guard < 200; ++guard)
  {
    const double x = (t - ta) * scale;
    const double v = s * evalPower(c, x);
    const bool holds = v > 0.0;
    (holds ? lo : hi) = t;
    (holds ? vLo : vHi) = v;
    const double tol = 1e-12 * (1.0 + std::abs(hi));
    if (hi - lo <= tol)
      break;
    const double dv = s * ((3.0 * c[3] * x + 2.0 * c[2]) * x + c[1]) * scale; // dv/dt
    const double step = dv != 0.0 ? -v / dv : 0.0;
    if (dv != 0.0 && std::abs(step) < 0.5 * tol)
    {
      t += holds ? 0.5 * tol : -0.5 * tol; // converged: just past the root closes the bracket
      continue;
    }
    if (hi - lo <= 0.5 * reference)
    {
      reference = hi - lo;
      steps = 0;
    }
    else if (++steps >= 3 && std::abs(step) > 1e-3 * (hi - lo)) // three steps without halving
    {                                                              // the bracket, nor converging
      reference = hi - lo;
      steps = 0;
      t = 0.5 * (lo + hi);
      continue;
    }
    t += step;
    if (!(t > lo && t < hi))
      t = secant();
  }
  return hi;
}

/// Where the cubic with Bernstein coefficients b (x in [0, 1]) on the piece [ta, tb] of a segment
/// (x = (t - ta) / (tb - ta)) changes sign, in increasing order, each as the first t (to
/// 1e-12 (1 + |t|)) where the sign is no longer the one before. Returns how many (at most 3), or -1
/// where it cannot tell them apart from rounding with `margin`: the value at an end or at a critical
/// point within `margin` of 0 (a root at a piece's end, a tangency, a cubic that is 0 all along).
inline int signChanges(const double b[4], double ta, double tb, double margin, double roots[3])
{
  if (!(std::abs(b[0]) > margin && std::abs(b[3]) > margin))
    return -1;
  if (allAbove(b, margin) || (b[0] < -margin && b[1] < -margin && b[2] < -margin && b[3] < -margin))
    return 0;
  double c[4];
  powerFromBernstein(b, c);
  const double scale = 1.0 / (tb - ta);
  auto at = [&](double x) { return x <= 0.0 ? ta : x >= 1.0 ? tb : ta + (tb - ta) * x; };
  if ((b[0] > 0.0) != (b[3] > 0.0) && oneSignChange(b, margin))
  {
    roots[0] = lastOfSign(c, ta, scale, b[0] > 0.0 ? 1.0 : -1.0, ta, tb);
    return 1;
  }
  // Critical points: the roots of p'(x) = c1 + 2 c2 x + 3 c3 x^2 in (0, 1). Between them and the
  // ends p is monotone, so each part has a root exactly where its ends' signs differ.
  double x[4] = { 0.0 }, v[4] = { b[0] };
  int n = 1;
  const double qa = 3.0 * c[3], qb = 2.0 * c[2], qc = c[1];
  double r[2];
  int nr = 0;
  if (qa != 0.0)
  {
    const double disc = qb * qb - 4.0 * qa * qc;
    if (disc >= 0.0)
    {
      const double q = -0.5 * (qb + std::copysign(std::sqrt(disc), qb));
      r[nr++] = q / qa;
      if (q != 0.0)
        r[nr++] = qc / q;
    }
  }
  else if (qb != 0.0)
    r[nr++] = -qc / qb;
  if (nr == 2 && r[1] < r[0])
    std::swap(r[0], r[1]);
  for (int i = 0; i < nr; ++i)
    if (r[i] > 0.0 && r[i] < 1.0 && (n == 1 || r[i] > x[n - 1]))
    {
      x[n] = r[i];
      v[n] = evalPower(c, r[i]);
      if (!(std::abs(v[n]) > margin))
        return -1; // a tangency, or too close to one to tell
      ++n;
    }
  x[n] = 1.0;
  v[n] = b[3];
  ++n;
  int count = 0;
  for (int i = 0; i + 1 < n; ++i)
    if ((v[i] > 0.0) != (v[i + 1] > 0.0))
      roots[count++] = lastOfSign(c, ta, scale, v[i] > 0.0 ? 1.0 : -1.0, at(x[i]), at(x[i + 1]));
  return count;
}
}
