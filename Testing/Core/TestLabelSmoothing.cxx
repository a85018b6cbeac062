// SPDX-License-Identifier: GPL-3.0-or-later
// Smooth label maps (LabelInterpolation::Smooth, labelInterfaceWeights): interfaces below the
// voxel size on label maps sampled from known shapes, inside the band the voxels allow.
#include "HierarchicalOracle.h"
#include "LabelMapDomain.h"
#include "LabelPieces.h"
#include "LabelSmoothing.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <random>

using namespace omesh;

namespace
{
const std::array<double, 9> kIdentity{ 1, 0, 0, 0, 1, 0, 0, 0, 1 };

/// A label map sampled at voxel centres (point convention: centre i at origin + i * spacing) from
/// `labelAt(world point)`.
struct SampledMap
{
  std::array<int, 3> dims;
  Vec3 spacing;
  std::vector<int> labels;

  SampledMap(const std::array<int, 3>& d, const Vec3& h, const std::function<int(const Vec3&)>& labelAt)
    : dims(d)
    , spacing(h)
  {
    for (int k = 0; k < d[2]; ++k)
      for (int j = 0; j < d[1]; ++j)
        for (int i = 0; i < d[0]; ++i)
          labels.push_back(labelAt(centre(i, j, k)));
  }
  Vec3 centre(int i, int j, int k) const { return { i * spacing.x, j * spacing.y, k * spacing.z }; }
  std::shared_ptr<LabelMapDomain> domain(LabelInterpolation mode, const LabelSmoothingOptions& options = {}) const
  {
    return std::make_shared<LabelMapDomain>(dims, labels,
      LabelMapDomain::pointCenteredWorldToVoxel({ 0, 0, 0 }, spacing, kIdentity), 0, "sampled", mode, options);
  }
};

/// Where the domain's label changes along grid-parallel lines through the map (every axis, lines
/// spaced `step` voxels apart, offset from the voxel centres): the distance of each change to the
/// true surface, as |signed distance| / `unit`.
struct InterfaceDistances
{
  double mean = 0.0, max = 0.0;
  size_t count = 0;
};

InterfaceDistances interfaceDistances(const LabelMapDomain& domain, const SampledMap& m,
  const std::function<double(const Vec3&)>& distance, double step = 0.37)
{
  InterfaceDistances out;
  const double unit = std::cbrt(m.spacing.x * m.spacing.y * m.spacing.z);
  double sum = 0.0;
  for (int axis = 0; axis < 3; ++axis)
  {
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    for (double a = 0.5; a < m.dims[u] - 1.5; a += step)
      for (double b = 0.5; b < m.dims[v] - 1.5; b += step)
      {
        Vec3 p, q;
        p[u] = q[u] = a * m.spacing[u];
        p[v] = q[v] = b * m.spacing[v];
        p[axis] = 0.0;
        q[axis] = (m.dims[axis] - 1) * m.spacing[axis];
        std::vector<double> ts;
        domain.crossings(p, q, ts);
        for (size_t i = 2; i < ts.size(); ++i) // after the grid's ends
        {
          const double d = std::abs(distance(lerp(p, q, ts[i]))) / unit;
          sum += d;
          out.max = std::max(out.max, d);
          ++out.count;
        }
      }
  }
  out.mean = out.count ? sum / out.count : 0.0;
  return out;
}

/// Volume of material `material` by sampling `perVoxel`^3 points per voxel of the map's grid.
double sampledVolume(const LabelMapDomain& domain, const SampledMap& m, int material, int perVoxel = 4)
{
  size_t inside = 0;
  const double f = 1.0 / perVoxel;
  for (int k = 0; k < (m.dims[2] - 1) * perVoxel; ++k)
    for (int j = 0; j < (m.dims[1] - 1) * perVoxel; ++j)
      for (int i = 0; i < (m.dims[0] - 1) * perVoxel; ++i)
        inside += domain.material({ (i + 0.5) * f * m.spacing.x, (j + 0.5) * f * m.spacing.y,
                    (k + 0.5) * f * m.spacing.z }) == material;
  return inside * f * f * f * m.spacing.x * m.spacing.y * m.spacing.z;
}

Vec3 randomUnit(std::mt19937& rng)
{
  std::normal_distribution<double> n;
  const Vec3 v{ n(rng), n(rng), n(rng) };
  return (1.0 / norm(v)) * v;
}
}

TEST(LabelSmoothing, EveryVoxelCentreKeepsItsLabelAndLayersStayConnected)
{
  // noisy labels (0-3, a one-voxel layer, lone voxels): at every voxel centre the label is its
  // own (the interfaces stay in the half voxel the voxels allow), and along every voxel edge
  // between two centres of one label that label holds all the way (a layer one voxel thin stays
  // connected)
  std::mt19937 rng(11);
  const SampledMap m({ 14, 12, 10 }, { 1, 1, 1 }, [&](const Vec3& p) {
    int l = (p.x - 7) * (p.x - 7) + (p.y - 6) * (p.y - 6) + (p.z - 5) * (p.z - 5) < 16 ? 1 : 0;
    if (std::abs(p.y - 3) < 0.1)
      l = 2;
    if (rng() % 9 == 0)
      l = static_cast<int>(rng() % 4);
    return l;
  });
  const auto domain = m.domain(LabelInterpolation::Smooth);
  size_t edges = 0;
  for (int k = 0; k < m.dims[2]; ++k)
    for (int j = 0; j < m.dims[1]; ++j)
      for (int i = 0; i < m.dims[0]; ++i)
      {
        const int label = m.labels[i + m.dims[0] * (j + m.dims[1] * k)];
        const int material = label == 0 ? kOutside : label;
        ASSERT_EQ(domain->material(m.centre(i, j, k)), material) << i << " " << j << " " << k;
        const int next[3][3] = { { i + 1, j, k }, { i, j + 1, k }, { i, j, k + 1 } };
        for (const auto& n : next)
        {
          if (n[0] >= m.dims[0] || n[1] >= m.dims[1] || n[2] >= m.dims[2] ||
            m.labels[n[0] + m.dims[0] * (n[1] + m.dims[1] * n[2])] != label)
            continue;
          ++edges;
          for (int s = 1; s < 8; ++s)
            ASSERT_EQ(domain->material(lerp(m.centre(i, j, k), m.centre(n[0], n[1], n[2]), s / 8.0)), material);
        }
      }
  EXPECT_GT(edges, 2000u);
}

TEST(LabelSmoothing, TiltedPlanesAreFoundBelowTheVoxelSize)
{
  // half-spaces at random tilts: the staircase a plane leaves in the voxels is smoothed away.
  // Trilinear follows the staircase (about 0.15 voxel on average); Smooth keeps within 0.08 on
  // average and 0.3 at most.
  std::mt19937 rng(3);
  for (int trial = 0; trial < 3; ++trial)
  {
    const Vec3 n = randomUnit(rng), c{ 12.3, 11.8, 12.1 };
    auto distance = [&](const Vec3& p) { return dot(p - c, n); };
    const SampledMap m({ 25, 25, 25 }, { 1, 1, 1 }, [&](const Vec3& p) { return distance(p) < 0 ? 1 : 0; });
    const InterfaceDistances smooth = interfaceDistances(*m.domain(LabelInterpolation::Smooth), m, distance);
    const InterfaceDistances trilinear = interfaceDistances(*m.domain(LabelInterpolation::Trilinear), m, distance);
    SCOPED_TRACE("trial " + std::to_string(trial));
    EXPECT_GT(smooth.count, 1000u);
    EXPECT_LT(smooth.mean, 0.08);
    EXPECT_LT(smooth.max, 0.3);
    EXPECT_GT(trilinear.mean, 0.1); // the test tells the two apart
  }
}

TEST(LabelSmoothing, SpheresKeepTheirRadiusAndVolume)
{
  // balls of radius 4.5 and 8 voxels, centres off the grid: interfaces within 0.08 voxel on
  // average, 0.3 at most, and the volume (sampled from the oracle) within 2 % of the exact one
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> jitter(-0.5, 0.5);
  for (double radius : { 4.5, 8.0 })
  {
    const Vec3 c{ 11 + jitter(rng), 11 + jitter(rng), 11 + jitter(rng) };
    auto distance = [&](const Vec3& p) { return norm(p - c) - radius; };
    const SampledMap m({ 23, 23, 23 }, { 1, 1, 1 }, [&](const Vec3& p) { return distance(p) < 0 ? 3 : 0; });
    const auto domain = m.domain(LabelInterpolation::Smooth);
    const InterfaceDistances d = interfaceDistances(*domain, m, distance);
    SCOPED_TRACE("radius " + std::to_string(radius));
    EXPECT_LT(d.mean, 0.08);
    EXPECT_LT(d.max, 0.3);
    const double exact = 4.0 / 3.0 * M_PI * radius * radius * radius;
    EXPECT_NEAR(sampledVolume(*domain, m, 3), exact, 0.02 * exact);
  }
}

TEST(LabelSmoothing, AThinShellKeepsItsVolumeAndStaysOneLayer)
{
  // a shell 1.5 voxels thick (label 1) around a core (label 2), at 6 placements off the grid:
  // its volume within 3 % of the exact one on average and 5 % at worst (the voxel count itself is
  // up to 3 % off here), and every ray from the centre crosses it (no hole)
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> jitter(-0.5, 0.5);
  const double inner = 7.0, outer = 8.5;
  const double exact = 4.0 / 3.0 * M_PI * (outer * outer * outer - inner * inner * inner);
  double sum = 0.0;
  for (int placement = 0; placement < 6; ++placement)
  {
    SCOPED_TRACE("placement " + std::to_string(placement));
    const Vec3 c{ 12 + jitter(rng), 12 + jitter(rng), 12 + jitter(rng) };
    const SampledMap m({ 25, 25, 25 }, { 1, 1, 1 }, [&](const Vec3& p) {
      const double r = norm(p - c);
      return r < inner ? 2 : r < outer ? 1 : 0;
    });
    const auto domain = m.domain(LabelInterpolation::Smooth);
    const double error = std::abs(sampledVolume(*domain, m, 1, 3) - exact) / exact;
    EXPECT_LT(error, 0.05);
    sum += error;
    for (int ray = 0; ray < 500; ++ray)
    {
      const Vec3 dir = randomUnit(rng);
      bool shell = false;
      for (int s = 0; s <= 300 && !shell; ++s)
        shell = domain->material(c + (inner - 1.0 + 3.0 * s / 300.0) * dir) == 1;
      ASSERT_TRUE(shell) << "ray " << ray;
    }
  }
  EXPECT_LT(sum / 6.0, 0.03);
}

TEST(LabelSmoothing, OneLabelOnBothSidesOfAThinLayerKeepsTheLayer)
{
  // A hollow shell 1.5 voxels thick with the background inside and out, and two balls of one label
  // across a gap 1.5 voxels wide, at random placements: one estimate of the background (of the
  // balls' label) mixes both sides of the thin layer and thins it (shell: 0.15 voxel on average,
  // 0.6 at worst; balls: 0.5-0.8 at worst across the gap). Each side's own piece is estimated
  // alone: the shell within 0.06 voxel on average and 0.35 at worst, its volume within 3 %; the
  // balls within 0.45 (0.27-0.4).
  LabelSmoothingOptions oneEstimate;
  oneEstimate.pieceVoxels = 0;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> jitter(-0.5, 0.5);
  const double inner = 7.0, outer = 8.5, radius = 6.0, gap = 1.5;
  const double shellVolume = 4.0 / 3.0 * M_PI * (outer * outer * outer - inner * inner * inner);
  for (int placement = 0; placement < 3; ++placement)
  {
    SCOPED_TRACE("placement " + std::to_string(placement));
    const Vec3 c{ 12 + jitter(rng), 12 + jitter(rng), 12 + jitter(rng) };
    auto shellDistance = [&](const Vec3& p) { return std::max(norm(p - c) - outer, inner - norm(p - c)); };
    const SampledMap shell({ 25, 25, 25 }, { 1, 1, 1 }, [&](const Vec3& p) { return shellDistance(p) < 0 ? 1 : 0; });
    const auto domain = shell.domain(LabelInterpolation::Smooth);
    const InterfaceDistances d = interfaceDistances(*domain, shell, shellDistance);
    EXPECT_LT(d.mean, 0.06);
    EXPECT_LT(d.max, 0.35);
    EXPECT_NEAR(sampledVolume(*domain, shell, 1, 3), shellVolume, 0.03 * shellVolume);
    EXPECT_GT(interfaceDistances(*shell.domain(LabelInterpolation::Smooth, oneEstimate), shell, shellDistance).mean, 0.1);

    const Vec3 axis = randomUnit(rng), a = c - (radius + 0.5 * gap) * axis, b = c + (radius + 0.5 * gap) * axis;
    auto ballsDistance = [&](const Vec3& p) { return std::min(norm(p - a), norm(p - b)) - radius; };
    const SampledMap balls({ 30, 30, 30 }, { 1, 1, 1 }, [&](const Vec3& p) {
      return ballsDistance(p + Vec3{ -2.5, -2.5, -2.5 }) < 0 ? 1 : 0;
    });
    auto shifted = [&](const Vec3& p) { return ballsDistance(p + Vec3{ -2.5, -2.5, -2.5 }); };
    const InterfaceDistances g = interfaceDistances(*balls.domain(LabelInterpolation::Smooth), balls, shifted);
    const InterfaceDistances one = interfaceDistances(*balls.domain(LabelInterpolation::Smooth, oneEstimate), balls, shifted);
    EXPECT_LT(g.mean, 0.06);
    EXPECT_LT(g.max, 0.45);
    EXPECT_LT(g.max, one.max - 0.1);
  }
}

TEST(LabelSmoothing, SmallPiecesKeepTheirVoxelVolume)
{
  // blocks of 4 x 4 x 3 and 3 x 3 x 2 voxels and a ball of radius 3 on a CT-like grid (2.4 voxels
  // along z) inside another label: each piece keeps its voxel count's volume, and every voxel
  // centre its label. Off, a speck's corners are all there is of it: the bend step (kBendShift)
  // pushes the small block's faces out by about 0.1 voxel (a quarter more volume); the ball
  // stays within 5 % (its caps at the poles; a tenth too small without them).
  auto blockOf = [](int nx, int nz) {
    return SampledMap({ 12, 12, 11 }, { 1, 1, 1 }, [=](const Vec3& p) {
      return p.x >= 4 && p.x <= 3 + nx && p.y >= 4 && p.y <= 3 + nx && p.z >= 4 && p.z <= 3 + nz ? 5 : 0;
    });
  };
  const SampledMap block = blockOf(4, 3), speck = blockOf(3, 2);
  const Vec3 c{ 8.8, 8.6, 9.4 };
  const SampledMap ball({ 36, 36, 16 }, { 0.5, 0.5, 1.25 }, [&](const Vec3& p) {
    const double r = norm(p - c);
    return r < 3.0 ? 2 : r < 6.5 ? 1 : 0;
  });
  for (const auto& [m, label] :
    { std::pair<const SampledMap*, int>{ &block, 5 }, { &speck, 5 }, { &ball, 2 } })
  {
    const double voxels = static_cast<double>(std::count(m->labels.begin(), m->labels.end(), label)) *
      m->spacing.x * m->spacing.y * m->spacing.z;
    const auto domain = m->domain(LabelInterpolation::Smooth);
    EXPECT_NEAR(sampledVolume(*domain, *m, label, 6), voxels, 0.02 * voxels) << "label " << label;
    for (int k = 0; k < m->dims[2]; ++k)
      for (int j = 0; j < m->dims[1]; ++j)
        for (int i = 0; i < m->dims[0]; ++i)
          ASSERT_EQ(domain->material(m->centre(i, j, k)),
            m->labels[i + m->dims[0] * (j + static_cast<size_t>(m->dims[1]) * k)] == 0 ? -1 : m->labels[i + m->dims[0] * (j + static_cast<size_t>(m->dims[1]) * k)]);
  }
  LabelSmoothingOptions off;
  off.smallPieceVoxels = 0;
  EXPECT_GT(sampledVolume(*speck.domain(LabelInterpolation::Smooth, off), speck, 5, 6), 1.15 * 18);
  const double ballVoxels = static_cast<double>(std::count(ball.labels.begin(), ball.labels.end(), 2)) * 0.5 * 0.5 * 1.25;
  const double ballOff = sampledVolume(*ball.domain(LabelInterpolation::Smooth, off), ball, 2, 6);
  EXPECT_NEAR(ballOff, ballVoxels, 0.05 * ballVoxels);
  LabelSmoothingOptions flat = off;
  flat.fitPlateaus = false;
  EXPECT_LT(sampledVolume(*ball.domain(LabelInterpolation::Smooth, flat), ball, 2, 6), 0.92 * ballVoxels);
}

TEST(LabelSmoothing, AnisotropicVoxelsFollowTheSurfaceBetterThanTrilinear)
{
  // a CT-like grid (0.5 x 0.5 x 1.25 mm) sampling a ball of radius 5 mm: Smooth's interfaces at
  // most 0.7 of Trilinear's distance on average
  const Vec3 c{ 8.9, 9.1, 9.6 };
  auto distance = [&](const Vec3& p) { return norm(p - c) - 5.0; };
  const SampledMap m({ 37, 37, 16 }, { 0.5, 0.5, 1.25 }, [&](const Vec3& p) { return distance(p) < 0 ? 1 : 0; });
  const InterfaceDistances smooth = interfaceDistances(*m.domain(LabelInterpolation::Smooth), m, distance);
  const InterfaceDistances trilinear = interfaceDistances(*m.domain(LabelInterpolation::Trilinear), m, distance);
  EXPECT_LT(smooth.mean, 0.7 * trilinear.mean);
  EXPECT_LT(smooth.max, trilinear.max);
}

TEST(LabelSmoothing, CrossingsFindEveryChangeDenseSamplingSees)
{
  // the walk of Trilinear, with weights, in cells of two labels (with three it samples, as
  // Trilinear's): every change of material that dense sampling sees on a segment is a reported
  // crossing (to the sampling's resolution), and each crossing is a change
  std::mt19937 rng(17);
  const SampledMap m({ 16, 14, 12 }, { 1, 1, 1 }, [&](const Vec3& p) {
    int l = (p.x - 8) * (p.x - 8) + (p.y - 7) * (p.y - 7) + 2 * (p.z - 6) * (p.z - 6) < 25 ? 1 : 0;
    if (std::abs(p.x - 11) < 0.1)
      l = 1 - l; // a one-voxel layer
    if (rng() % 15 == 0)
      l = 1 - l;
    return l;
  });
  const auto domain = m.domain(LabelInterpolation::Smooth);
  std::uniform_real_distribution<double> where(0.2, 10.8), step(-3.0, 3.0);
  constexpr int kDense = 1024;
  size_t changes = 0;
  for (int n = 0; n < 1500; ++n)
  {
    const Vec3 a{ where(rng) * 15.0 / 11.0, where(rng) * 13.0 / 11.0, where(rng) };
    Vec3 b = a + Vec3{ step(rng), step(rng), step(rng) };
    for (int i = 0; i < 3; ++i)
      b[i] = std::clamp(b[i], 0.05, (m.dims[i] - 1) - 0.05);
    std::vector<double> ts;
    domain->crossings(a, b, ts);
    const std::vector<double> found(ts.begin() + 2, ts.end());
    int before = domain->material(a);
    for (int k = 1; k <= kDense; ++k)
    {
      const int now = domain->material(lerp(a, b, static_cast<double>(k) / kDense));
      if (now == before)
        continue;
      ++changes;
      const double lo = (k - 1.0) / kDense, hi = static_cast<double>(k) / kDense;
      EXPECT_TRUE(std::any_of(found.begin(), found.end(), [&](double t) { return t >= lo - 1e-9 && t <= hi + 1e-9; }))
        << "segment " << n << ": a change in [" << lo << ", " << hi << "] not reported";
      before = now;
    }
    for (double t : found)
      EXPECT_NE(domain->material(lerp(a, b, std::max(t - 1e-7, 0.0))), domain->material(lerp(a, b, std::min(t + 1e-7, 1.0))))
        << "segment " << n << ": a crossing at " << t << " where nothing changes";
  }
  EXPECT_GT(changes, 500u);
}

TEST(LabelSmoothing, ProgressIsReportedAndStopsTheWork)
{
  const SampledMap m({ 20, 20, 20 }, { 1, 1, 1 }, [](const Vec3& p) { return norm(p - Vec3{ 10, 10, 10 }) < 6 ? 1 : 0; });
  std::vector<double> heard;
  LabelSmoothingOptions options;
  options.progress = [&](double f) {
    heard.push_back(f);
    return true;
  };
  m.domain(LabelInterpolation::Smooth, options);
  ASSERT_GT(heard.size(), 3u);
  EXPECT_TRUE(std::is_sorted(heard.begin(), heard.end()));
  EXPECT_DOUBLE_EQ(heard.back(), 1.0);
  options.progress = [](double f) { return f < 0.3; };
  EXPECT_THROW(m.domain(LabelInterpolation::Smooth, options), LabelSmoothingAborted);
}

TEST(LabelSmoothing, ALargeBallsPoleOnAGridAxisIsFoundFromTheStaircaseAroundIt)
{
  // Where a large ball just reaches past a grid plane, its voxels leave a flat patch several
  // voxels across at the pole (radius 12, pole 0.06 voxel past a voxel centre: a patch 4.7 voxels
  // in radius, on the grid's axis: the worst placement). Without the caps (fitPlateaus false) the
  // filters keep the patch nearly flat, 0.16-0.35 voxel inside the ball at the pole, the wide one
  // somewhat less than the narrow one alone; the cap fitted to the walls around finds the pole
  // within 0.1 voxel, and the ball's worst interface point within 0.2.
  LabelSmoothingOptions flat, flatNarrow;
  flat.fitPlateaus = false;
  flatNarrow.fitPlateaus = false;
  flatNarrow.wideSigma = 0.0;
  for (double past : { 0.06, 0.12, 0.2 })
    for (double radius : { 9.0, 12.0 })
    {
      const Vec3 c{ 3.0 + past + radius, radius + 3.3, radius + 2.8 }; // the pole at x = 3 + past
      auto distance = [&](const Vec3& p) { return norm(p - c) - radius; };
      const int n = static_cast<int>(std::ceil(2.0 * radius)) + 7;
      const SampledMap m({ n, n, n }, { 1, 1, 1 }, [&](const Vec3& p) { return distance(p) < 0 ? 1 : 0; });
      SCOPED_TRACE("radius " + std::to_string(radius) + ", pole " + std::to_string(past) + " past a voxel centre");
      auto poleError = [&](const LabelMapDomain& domain) {
        std::vector<double> ts;
        const Vec3 p{ 0.0, c.y, c.z }, q{ c.x, c.y, c.z };
        domain.crossings(p, q, ts);
        EXPECT_GE(ts.size(), 3u);
        return ts.size() < 3 ? 1.0 : std::abs(lerp(p, q, ts[2]).x - (c.x - radius));
      };
      const auto capped = m.domain(LabelInterpolation::Smooth);
      const auto wide = m.domain(LabelInterpolation::Smooth, flat);
      const double cappedAtPole = poleError(*capped), wideAtPole = poleError(*wide);
      EXPECT_LT(cappedAtPole, 0.1);
      EXPECT_LT(cappedAtPole, wideAtPole - 0.1);
      EXPECT_LT(wideAtPole, poleError(*m.domain(LabelInterpolation::Smooth, flatNarrow)) - 0.03);
      const InterfaceDistances all = interfaceDistances(*capped, m, distance);
      EXPECT_LT(all.mean, 0.06);
      EXPECT_LT(all.max, 0.2);
      EXPECT_LT(all.max, interfaceDistances(*wide, m, distance).max);
    }
}

TEST(LabelSmoothing, BallsOnACTGridKeepTheirPolesAlongTheCoarseAxis)
{
  // Balls of radius 3 to 6.5 mm, alone and one inside another, on a 0.5 x 0.5 x 1.25 mm grid at
  // random offsets: a pole along z lies anywhere within a 1.25 mm slice, and the patch of its last
  // slice is up to 7 fine voxels across. Within 0.35 voxel (of the geometric mean, 0.68 mm) at
  // worst and 0.08 on average (0.02-0.07); 0.39-0.7 at worst without the caps.
  const Vec3 h{ 0.5, 0.5, 1.25 };
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> offset(-0.5, 0.5);
  LabelSmoothingOptions flat;
  flat.fitPlateaus = false;
  double worstFlat = 0.0;
  for (double radius : { 3.0, 5.0, 6.5 })
    for (int nested = 0; nested < 2; ++nested)
    {
      const std::array<int, 3> dims{ static_cast<int>(2 * radius / h.x) + 8, static_cast<int>(2 * radius / h.y) + 8,
        static_cast<int>(2 * radius / h.z) + 8 };
      const Vec3 c{ (dims[0] - 1) * h.x / 2 + offset(rng) * h.x, (dims[1] - 1) * h.y / 2 + offset(rng) * h.y,
        (dims[2] - 1) * h.z / 2 + offset(rng) * h.z };
      const Vec3 inner = c + Vec3{ offset(rng), offset(rng), offset(rng) };
      if (nested && radius < 5.0)
        continue; // (a core under 2 mm: a slice or two)
      const double r2 = nested ? 0.5 * radius : 0.0;
      auto distance = [&](const Vec3& p) {
        const double outer = norm(p - c) - radius;
        const double core = norm(p - inner) - r2;
        return nested && std::abs(core) < std::abs(outer) ? core : outer;
      };
      const SampledMap m(dims, h, [&](const Vec3& p) {
        return nested && norm(p - inner) < r2 ? 2 : norm(p - c) < radius ? 1 : 0;
      });
      SCOPED_TRACE("radius " + std::to_string(radius) + (nested ? ", a ball inside" : ""));
      const InterfaceDistances capped = interfaceDistances(*m.domain(LabelInterpolation::Smooth), m, distance);
      EXPECT_LT(capped.mean, 0.08);
      EXPECT_LT(capped.max, 0.35);
      worstFlat = std::max(worstFlat, interfaceDistances(*m.domain(LabelInterpolation::Smooth, flat), m, distance).max);
    }
  EXPECT_GT(worstFlat, 0.4);
}

namespace
{
/// A cube of half-size `half` turned by a random rotation (its columns: the cube's axes).
struct TiltedCube
{
  Vec3 centre;
  double half;
  std::array<Vec3, 3> axes;

  TiltedCube(const Vec3& c, double h, std::mt19937& rng)
    : centre(c)
    , half(h)
  {
    axes[0] = randomUnit(rng);
    Vec3 t = randomUnit(rng);
    axes[1] = (1.0 / norm(t - dot(t, axes[0]) * axes[0])) * (t - dot(t, axes[0]) * axes[0]);
    axes[2] = cross(axes[0], axes[1]);
  }
  Vec3 local(const Vec3& p) const { return { dot(p - centre, axes[0]), dot(p - centre, axes[1]), dot(p - centre, axes[2]) }; }
  /// The exact signed distance (negative inside).
  double distance(const Vec3& p) const
  {
    const Vec3 l = local(p);
    const Vec3 q{ std::abs(l.x) - half, std::abs(l.y) - half, std::abs(l.z) - half };
    const Vec3 out{ std::max(q.x, 0.0), std::max(q.y, 0.0), std::max(q.z, 0.0) };
    return norm(out) + std::min(std::max({ q.x, q.y, q.z }), 0.0);
  }
  /// How far p lies from the cube's nearest edge line.
  double edgeDistance(const Vec3& p) const
  {
    const Vec3 l = local(p);
    std::array<double, 3> q{ half - std::abs(l.x), half - std::abs(l.y), half - std::abs(l.z) };
    std::sort(q.begin(), q.end());
    return std::hypot(q[0], q[1]);
  }
};
}

TEST(LabelSmoothing, TiltedCubesKeepTheirEdgesAndCorners)
{
  // Cubes at random tilts: the smoothing alone rounds each edge by about a voxel and bulges the
  // faces beside it (0.09-0.13 voxel on average, 0.5-0.6 at most); with their faces found, the
  // planes' distance put near the edges and the values fitted so that the trilinear interpolant
  // follows the planes between the voxel centres (the distances alone chamfer every edge, 0.42
  // voxel at a corner), the interfaces come within 0.06 voxel on average (0.035-0.05 here) and
  // 0.33 at most (0.25-0.29), closer than without by a third, and so does the share of the mean
  // that lies within a voxel of an edge (nearEdge: the distance there, 0 elsewhere).
  std::mt19937 rng(7);
  LabelSmoothingOptions round;
  round.sharpEdges = false;
  for (int trial = 0; trial < 3; ++trial)
  {
    const TiltedCube cube(Vec3{ 12.4, 12.1, 12.7 } + 0.5 * randomUnit(rng), 5.5, rng);
    auto distance = [&](const Vec3& p) { return cube.distance(p); };
    auto nearEdge = [&](const Vec3& p) { return cube.edgeDistance(p) < 1.0 ? cube.distance(p) : 0.0; };
    const SampledMap m({ 26, 26, 26 }, { 1, 1, 1 }, [&](const Vec3& p) { return distance(p) < 0 ? 1 : 0; });
    const auto sharpDomain = m.domain(LabelInterpolation::Smooth), roundDomain = m.domain(LabelInterpolation::Smooth, round);
    const InterfaceDistances sharp = interfaceDistances(*sharpDomain, m, distance);
    const InterfaceDistances rounded = interfaceDistances(*roundDomain, m, distance);
    const InterfaceDistances sharpEdges = interfaceDistances(*sharpDomain, m, nearEdge);
    const InterfaceDistances roundEdges = interfaceDistances(*roundDomain, m, nearEdge);
    SCOPED_TRACE("trial " + std::to_string(trial));
    EXPECT_LT(sharp.mean, 0.06);
    EXPECT_LT(sharp.max, 0.33);
    EXPECT_LT(sharp.mean, 0.67 * rounded.mean);
    EXPECT_LT(sharpEdges.mean, 0.67 * roundEdges.mean);
    EXPECT_LT(sharp.max, rounded.max);
  }
}

TEST(LabelSmoothing, BallsShellsAndCrossingBallsHaveNoSharpEdges)
{
  // Shapes with no flat faces: the weights are the same with and without looking for sharp edges
  // (a small ball bends as sharply as an edge; two balls crossing meet at a sharp crease between
  // curved faces; a thin shell's two sides face each other).
  LabelSmoothingOptions round;
  round.sharpEdges = false;
  const Vec3 c{ 11.3, 11.6, 11.2 }, d{ 17.9, 15.2, 13.1 };
  const std::vector<std::pair<std::string, std::function<int(const Vec3&)>>> shapes{
    { "ball 3.5", [&](const Vec3& p) { return norm(p - c) < 3.5 ? 1 : 0; } },
    { "ball 7", [&](const Vec3& p) { return norm(p - c) < 7.0 ? 1 : 0; } },
    { "shell", [&](const Vec3& p) { return norm(p - c) < 6.0 ? 2 : norm(p - c) < 7.5 ? 1 : 0; } },
    { "crossing balls", [&](const Vec3& p) { return norm(p - c) < 9.0 ? 2 : norm(p - d) < 9.0 ? 1 : 0; } },
  };
  for (const auto& [name, labelAt] : shapes)
  {
    const SampledMap m({ 32, 32, 30 }, { 1, 1, 1 }, labelAt);
    std::vector<uint16_t> index(m.labels.begin(), m.labels.end());
    const auto sharp = labelInterfaceWeights(m.dims, index, 3, { 1, 1, 1 });
    const auto rounded = labelInterfaceWeights(m.dims, index, 3, { 1, 1, 1 }, round);
    EXPECT_EQ(sharp, rounded) << name;
  }
}

TEST(LabelSmoothing, ANotchedCubeKeepsItsSmallFacesSharp)
{
  // A tilted cube with one octant cut away: three concave edges meet at a concave corner and the
  // notch's faces are small beside the cube's (under a tenth of the largest plane's samples, kept
  // as found around many voxels: largeVoxels). Voxels near a face the sharpening drops stay smooth
  // (the remaining planes alone once cut the material away there by up to 3 voxels). Closer than
  // without sharp edges on average (0.037-0.042 against 0.10-0.12 here; 0.050-0.056 with the
  // notch's faces dropped) and at worst (0.45-0.54 against 0.59-0.64; 0.53-0.58 dropped).
  std::mt19937 rng(11);
  LabelSmoothingOptions round;
  round.sharpEdges = false;
  for (int trial = 0; trial < 2; ++trial)
  {
    const TiltedCube cube(Vec3{ 14.2, 13.9, 14.4 } + 0.5 * randomUnit(rng), 7.0, rng);
    auto distance = [&](const Vec3& p) {
      const Vec3 l = cube.local(p);
      const double octant = l.x > 0 && l.y > 0 && l.z > 0 ? -std::min({ l.x, l.y, l.z })
                                                           : norm(Vec3{ std::min(l.x, 0.0), std::min(l.y, 0.0), std::min(l.z, 0.0) });
      return std::max(cube.distance(p), -octant);
    };
    const SampledMap m({ 30, 30, 30 }, { 1, 1, 1 }, [&](const Vec3& p) { return distance(p) < 0 ? 1 : 0; });
    const InterfaceDistances sharp = interfaceDistances(*m.domain(LabelInterpolation::Smooth), m, distance);
    const InterfaceDistances rounded = interfaceDistances(*m.domain(LabelInterpolation::Smooth, round), m, distance);
    SCOPED_TRACE("trial " + std::to_string(trial));
    EXPECT_LT(sharp.mean, 0.045);
    EXPECT_LT(sharp.mean, 0.5 * rounded.mean);
    EXPECT_LT(sharp.max, rounded.max - 0.05);
  }
}

TEST(LabelPieces, RunsGiveTheSixConnectedPiecesAFloodFillFinds)
{
  // random labels (three, clustered a little) on 13 x 11 x 9 voxels: the pieces as runs along x
  // against a flood fill over the six face neighbours, voxel by voxel, and fill() against at()
  const std::array<int, 3> dims{ 13, 11, 9 };
  std::mt19937 rng(3);
  std::vector<uint16_t> index(static_cast<size_t>(dims[0]) * dims[1] * dims[2]);
  for (size_t v = 0; v < index.size(); ++v)
    index[v] = v > 0 && rng() % 3 ? index[v - 1] : static_cast<uint16_t>(rng() % 3);
  const LabelPieces pieces(dims, index);
  std::vector<int> flood(index.size(), -1);
  int count = 0;
  for (size_t seed = 0; seed < index.size(); ++seed)
  {
    if (flood[seed] >= 0)
      continue;
    std::vector<size_t> stack{ seed };
    flood[seed] = count;
    while (!stack.empty())
    {
      const size_t v = stack.back();
      stack.pop_back();
      const int p[3] = { static_cast<int>(v % dims[0]), static_cast<int>(v / dims[0] % dims[1]),
        static_cast<int>(v / dims[0] / dims[1]) };
      const size_t stride[3] = { 1, static_cast<size_t>(dims[0]), static_cast<size_t>(dims[0]) * dims[1] };
      for (int a = 0; a < 3; ++a)
        for (int step : { -1, 1 })
        {
          if (p[a] + step < 0 || p[a] + step >= dims[a])
            continue;
          const size_t u = step < 0 ? v - stride[a] : v + stride[a];
          if (flood[u] < 0 && index[u] == index[v])
          {
            flood[u] = count;
            stack.push_back(u);
          }
        }
    }
    ++count;
  }
  ASSERT_EQ(pieces.count(), static_cast<size_t>(count));
  std::vector<int> pieceOfFlood(count, -1);
  std::vector<size_t> voxels(pieces.count(), 0);
  for (size_t v = 0; v < index.size(); ++v)
  {
    const uint32_t piece = pieces.at(v);
    ASSERT_LT(piece, pieces.count());
    EXPECT_EQ(pieces.label(piece), index[v]);
    if (pieceOfFlood[flood[v]] < 0)
      pieceOfFlood[flood[v]] = static_cast<int>(piece);
    ASSERT_EQ(pieceOfFlood[flood[v]], static_cast<int>(piece)) << "voxel " << v;
    ++voxels[piece];
  }
  for (uint32_t piece = 0; piece < pieces.count(); ++piece)
    EXPECT_EQ(pieces.voxels(piece), voxels[piece]);
  VoxelBox box;
  box.lo = { 2, 1, 3 };
  box.hi = { 11, 10, 8 };
  box.finish();
  const uint32_t piece = pieces.at(5 + dims[0] * (4 + static_cast<size_t>(dims[1]) * 5));
  std::vector<uint8_t> inside;
  pieces.fill(box, piece, inside);
  for (size_t o = 0; o < box.size; ++o)
  {
    int q[3];
    box.coordinates(o, q);
    const size_t v = (q[0] + box.lo[0]) + dims[0] * ((q[1] + box.lo[1]) + static_cast<size_t>(dims[1]) * (q[2] + box.lo[2]));
    EXPECT_EQ(inside[o] != 0, pieces.at(v) == piece);
  }
}
