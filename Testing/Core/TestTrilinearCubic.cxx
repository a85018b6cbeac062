// SPDX-License-Identifier: GPL-3.0-or-later
// The label map walk's cubics (TrilinearCubic.h): along a line inside a cell the trilinear
// interpolant is a cubic; its sign changes, found from Bernstein coefficients, critical points and
// Newton steps, must be those dense sampling of the trilinear interpolant itself sees.
#include "TrilinearCubic.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

using namespace omesh;

namespace
{
constexpr double kMargin = 1e-10; // the walk's

/// The trilinear interpolant of corner values v at fractions f, straight from its definition.
double trilinearAt(const double v[8], const double f[3])
{
  double sum = 0.0;
  for (int c = 0; c < 8; ++c)
  {
    double w = 1.0;
    for (int a = 0; a < 3; ++a)
      w *= ((c >> a) & 1) ? f[a] : 1.0 - f[a];
    sum += w * v[c];
  }
  return sum;
}

/// The interpolant at x of the line from fa to fb.
double alongLine(const double v[8], const double fa[3], const double fb[3], double x)
{
  const double f[3] = { fa[0] + x * (fb[0] - fa[0]), fa[1] + x * (fb[1] - fa[1]), fa[2] + x * (fb[2] - fa[2]) };
  return trilinearAt(v, f);
}

/// Bernstein coefficients of the power-basis cubic c[0] + c[1] x + c[2] x^2 + c[3] x^3.
void bernsteinFromPower(const double c[4], double b[4])
{
  b[0] = c[0];
  b[1] = c[0] + c[1] / 3.0;
  b[2] = c[0] + 2.0 * c[1] / 3.0 + c[2] / 3.0;
  b[3] = c[0] + c[1] + c[2] + c[3];
}

/// (x - r0)(x - r1)(x - r2) * s, as Bernstein coefficients; r2 = NaN: the quadratic (x - r0)(x - r1) + q.
void cubicWithRoots(double r0, double r1, double r2, double b[4], double s = 1.0)
{
  const double c[4] = { -r0 * r1 * r2 * s, (r0 * r1 + r0 * r2 + r1 * r2) * s, -(r0 + r1 + r2) * s, s };
  bernsteinFromPower(c, b);
}
}

TEST(TrilinearCubic, BernsteinCoefficientsAreTheInterpolantAlongTheLine)
{
  std::mt19937 rng(41);
  std::uniform_real_distribution<double> u(0.0, 1.0), value(-1.0, 1.0);
  for (int n = 0; n < 2000; ++n)
  {
    double v[8], fa[3], fb[3], b[4], c[4];
    for (double& x : v)
      x = value(rng);
    for (int a = 0; a < 3; ++a)
    {
      fa[a] = u(rng);
      fb[a] = n % 5 == a ? fa[a] : u(rng); // some lines in a plane of the cell
    }
    trilinear::bernsteinOnLine(v, fa, fb, b);
    trilinear::powerFromBernstein(b, c);
    EXPECT_NEAR(b[0], trilinearAt(v, fa), 1e-15);
    EXPECT_NEAR(b[3], trilinearAt(v, fb), 1e-15);
    for (int k = 0; k <= 16; ++k)
    {
      const double x = k / 16.0;
      ASSERT_NEAR(trilinear::evalPower(c, x), alongLine(v, fa, fb, x), 1e-14) << "line " << n << " x " << x;
    }
  }
}

TEST(TrilinearCubic, SignChangesAreThoseOfDenseSamplingOnRandomCellsOfTwoLabels)
{
  // Corners of two labels (the lead: +1 at one label's corners, -1 at the other's), random lines
  // through the cell, each a piece [ta, tb] of a segment. Every sign change dense sampling of the
  // trilinear interpolant sees must be found, in order, where it is; every change found must be
  // one (the sign differs just before and just after). A wrong "no root" (the certificate or the
  // count between critical points) misses the changes of the layers counted below.
  std::mt19937 rng(2026);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  constexpr int kDense = 2048;
  size_t decided = 0, undecided = 0, withChanges = 0, layersBetweenEndsOfOneSign = 0, missedByFourSamples = 0;
  size_t roots = 0;
  for (int n = 0; n < 20000; ++n)
  {
    double v[8];
    int plus = 0;
    for (double& x : v)
    {
      x = rng() % 2 ? 1.0 : -1.0;
      plus += x > 0.0;
    }
    if (plus == 0 || plus == 8)
      continue;
    double fa[3], fb[3];
    for (int a = 0; a < 3; ++a)
    {
      // near-corner and near-face lines too, where layers are thin
      fa[a] = n % 3 == 0 ? std::pow(u(rng), 4.0) : u(rng);
      fb[a] = n % 7 == a ? fa[a] : n % 3 == 0 ? 1.0 - std::pow(u(rng), 4.0) : u(rng);
    }
    const double ta = 0.5 * u(rng), tb = ta + 1e-3 + 0.5 * u(rng);
    double b[4], found[3];
    trilinear::bernsteinOnLine(v, fa, fb, b);
    const int count = trilinear::signChanges(b, ta, tb, kMargin, found);
    std::vector<double> dense(kDense + 1);
    for (int k = 0; k <= kDense; ++k)
      dense[k] = alongLine(v, fa, fb, static_cast<double>(k) / kDense);
    if (count < 0)
    {
      // only where rounding could decide: a value within the margin at an end, or a near-tangency
      const double smallest = std::min(std::abs(dense[0]), std::abs(dense[kDense]));
      const double grazing = *std::min_element(dense.begin(), dense.end(), [](double p, double q) {
        return std::abs(p) < std::abs(q);
      });
      EXPECT_TRUE(smallest <= kMargin || std::abs(grazing) < 1e-4) << "line " << n << " undecided";
      ++undecided;
      continue;
    }
    ++decided;
    roots += count;
    withChanges += count > 0;
    const double scale = tb - ta;
    // every root is a change of sign of the interpolant (tangencies are never reported)
    for (int r = 0; r < count; ++r)
    {
      ASSERT_GE(found[r], ta);
      ASSERT_LE(found[r], tb);
      if (r > 0)
        ASSERT_GT(found[r], found[r - 1]);
      const double x = (found[r] - ta) / scale, dx = 1e-9 / scale;
      const double before = alongLine(v, fa, fb, x - dx), after = alongLine(v, fa, fb, x + dx);
      EXPECT_LT(before * after, 0.0) << "line " << n << " root " << r << " at x " << x;
      // the sign before the root alternates with the root's index, starting from the start's
      EXPECT_EQ(before > 0.0, (b[0] > 0.0) == (r % 2 == 0)) << "line " << n << " root " << r;
    }
    // every change dense sampling sees lies between the samples around it: an odd number of
    // changes found in each sample interval whose ends differ in sign, an even number (a layer
    // thinner than the samples' spacing, or none) elsewhere
    std::vector<int> inInterval(kDense, 0);
    for (int r = 0; r < count; ++r)
      ++inInterval[std::min(kDense - 1, static_cast<int>((found[r] - ta) / scale * kDense))];
    for (int k = 0; k < kDense; ++k)
    {
      if (std::abs(dense[k]) < 1e-7 || std::abs(dense[k + 1]) < 1e-7)
        continue; // a change this close to a sample may be counted on either side of it
      const bool change = (dense[k] > 0.0) != (dense[k + 1] > 0.0);
      ASSERT_EQ(inInterval[k] % 2 == 1, change)
        << "line " << n << ": " << inInterval[k] << " changes found between samples " << k << " and " << k + 1;
    }
    // layers: changes where the piece's ends have the same sign; four samples (x = 1/4 .. 1)
    // see none of them when all four have the start's sign
    if (count >= 2 && (b[0] > 0.0) == (b[3] > 0.0))
    {
      ++layersBetweenEndsOfOneSign;
      bool seen = false;
      for (int s = 1; s <= 4; ++s)
        seen = seen || (alongLine(v, fa, fb, s / 4.0) > 0.0) != (b[0] > 0.0);
      missedByFourSamples += seen ? 0 : 1;
    }
  }
  EXPECT_GT(decided, 15000u);
  EXPECT_LT(undecided, decided / 100); // the walk samples these: about 1 in 1000
  EXPECT_GT(withChanges, 5000u);
  EXPECT_GT(layersBetweenEndsOfOneSign, 400u); // a certificate that said "no root" here would fail above
  EXPECT_GT(missedByFourSamples, 60u);         // thin layers that four samples a piece do not see
  RecordProperty("roots", static_cast<int>(roots));
  RecordProperty("decided", static_cast<int>(decided));
  RecordProperty("undecided", static_cast<int>(undecided));
  RecordProperty("withChanges", static_cast<int>(withChanges));
  RecordProperty("layers", static_cast<int>(layersBetweenEndsOfOneSign));
  RecordProperty("missedByFourSamples", static_cast<int>(missedByFourSamples));
}

TEST(TrilinearCubic, TangenciesRootsAtPieceEndsAndThinLayers)
{
  double b[4], t[3];
  // a double root (a tangency: the lead touches 0 and comes back) cannot be told from rounding
  cubicWithRoots(0.4, 0.4, 0.9, b);
  EXPECT_EQ(trilinear::signChanges(b, 0.0, 1.0, kMargin, t), -1);
  // the same just below 0 (a thin layer, 2e-4 wide) and just above (no change)
  const double below[4] = { 0.16 - 1e-8, -0.8, 1.0, 0.0 }, above[4] = { 0.16 + 1e-8, -0.8, 1.0, 0.0 };
  bernsteinFromPower(below, b);
  ASSERT_EQ(trilinear::signChanges(b, 0.0, 1.0, kMargin, t), 2);
  EXPECT_NEAR(t[0], 0.4 - 1e-4, 1e-12);
  EXPECT_NEAR(t[1], 0.4 + 1e-4, 1e-12);
  bernsteinFromPower(above, b);
  EXPECT_EQ(trilinear::signChanges(b, 0.0, 1.0, kMargin, t), 0);
  // roots at a piece's ends: undecided (the walk samples there); just inside them: found
  cubicWithRoots(0.0, 2.0, 3.0, b);
  EXPECT_EQ(trilinear::signChanges(b, 0.2, 0.6, kMargin, t), -1);
  cubicWithRoots(1.0, -2.0, 3.0, b);
  EXPECT_EQ(trilinear::signChanges(b, 0.2, 0.6, kMargin, t), -1);
  cubicWithRoots(1e-9, 2.0, 3.0, b);
  ASSERT_EQ(trilinear::signChanges(b, 0.2, 0.6, kMargin, t), 1);
  EXPECT_NEAR(t[0], 0.2 + 0.4e-9, 1e-12 * 1.2);
  cubicWithRoots(1.0 - 1e-9, -2.0, 3.0, b);
  ASSERT_EQ(trilinear::signChanges(b, 0.2, 0.6, kMargin, t), 1);
  EXPECT_NEAR(t[0], 0.6 - 0.4e-9, 1e-12 * 1.6);
  // three changes, in order, either sign at the start
  for (double s : { 1.0, -1.0 })
  {
    cubicWithRoots(0.2, 0.5, 0.8, b, s);
    ASSERT_EQ(trilinear::signChanges(b, 0.0, 1.0, kMargin, t), 3);
    EXPECT_NEAR(t[0], 0.2, 1e-12);
    EXPECT_NEAR(t[1], 0.5, 1e-12);
    EXPECT_NEAR(t[2], 0.8, 1e-12);
  }
  // 0 all along (a saddle cell's plane of ties): undecided
  const double saddle[8] = { 1, -1, -1, 1, 1, -1, -1, 1 }; // (1 - 2x)(1 - 2y)
  const double fa[3] = { 0.5, 0.0, 0.1 }, fb[3] = { 0.5, 1.0, 0.9 };
  trilinear::bernsteinOnLine(saddle, fa, fb, b);
  EXPECT_EQ(trilinear::signChanges(b, 0.0, 1.0, kMargin, t), -1);
  // a line through the saddle grazing its tie: a tangency of the trilinear lead itself
  // (1 - 2x)(1 - 2y) along x = y = s is (1 - 2s)^2: touches 0 at s = 1/2
  const double ga[3] = { 0.0, 0.0, 0.3 }, gb[3] = { 1.0, 1.0, 0.6 };
  trilinear::bernsteinOnLine(saddle, ga, gb, b);
  EXPECT_EQ(trilinear::signChanges(b, 0.0, 1.0, kMargin, t), -1);
  // each change found is the first t past it, to 1e-12 (1 + |t|), on pieces anywhere in [0, 1]
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int n = 0; n < 3000; ++n)
  {
    const double r = u(rng), ta = 0.9 * u(rng), tb = ta + 1e-6 + (1.0 - ta - 1e-6) * u(rng);
    cubicWithRoots(r, -0.5 - u(rng), 1.5 + u(rng), b, n % 2 ? 1.0 : -1.0);
    double c[4];
    trilinear::powerFromBernstein(b, c);
    const int count = trilinear::signChanges(b, ta, tb, kMargin, t);
    if (count < 0)
      continue; // a root within the margin of an end
    ASSERT_EQ(count, 1) << n;
    const double tol = 1e-12 * (1.0 + std::abs(t[0]));
    const double sign = b[0] > 0.0 ? 1.0 : -1.0;
    const double scale = 1.0 / (tb - ta); // as signChanges maps t to x
    EXPECT_LE(sign * trilinear::evalPower(c, (t[0] - ta) * scale), 0.0) << n;
    EXPECT_GT(sign * trilinear::evalPower(c, (t[0] - tol - ta) * scale), 0.0) << n;
  }
}
