// SPDX-License-Identifier: GPL-3.0-or-later
#include "LabelSmoothing.h"

#include "LabelEdgeSharpening.h"
#include "LabelPieces.h"
#include "LabelPlateauFit.h"
#include "VoxelBox.h"
#include "SmallPieceVolumes.h"
#include "WorkerThreads.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

// How the weights are found, per label L (in a box around L's boundary; where L has several
// 6-connected pieces, each large one on its own, L's others together: LabelPieces.h):
//  1. psi = the signed distance between voxel centres of L and the others (Felzenszwalb and
//     Huttenlocher's exact transform), less half a voxel: a staircase's distance function.
//  2. Rounds of: psi <- G * psi - (var / 2) Lap (G * psi) (G: a Gaussian of `sigma` voxels along
//     each axis, var its variance), then psi set to +delta / -delta at the
//     voxel centres where it took the wrong sign. The filter (a Gaussian with its second-order
//     error taken out: local quadratic regression's equivalent kernel) keeps every quadratic and,
//     in the continuum, every biharmonic function (a sphere's or a plane's distance among them),
//     and damps the staircase. The sign constraint keeps the zero set between the voxel centres
//     the labels allow. Then one curvature step, psi <- psi - beta h^2 Lap psi: the distance to
//     the nearest centre of the other side is shorter from a surface's concave side than from
//     its convex side (more centres lie near), which moves a staircase distance's zero set by
//     about beta h^2 times the mean curvature into the convex region it bounds (balls shrink).
//  2b. Step 2 again from the same start with a wider Gaussian (`wideSigma`), and the two blended
//     (blendWide): the wide one where the narrow one's zero set bends little within the wide
//     one's reach, the narrow one near edges, corners and small or thin parts. Where a large ball
//     touches a grid plane its voxels leave a flat patch several voxels across, wider than the
//     narrow filter's reach: the narrow filter keeps the patch flat (up to 0.4 voxel inside the
//     ball at its pole), the wide one carries the ball's curvature across it; near an edge the
//     wide one rounds more and bulges the faces beside it.
//  2c. Where the label's surface touches a grid plane, the flat patch its voxels leave gets the
//     height of a cap fitted to the staircase around it (fitLabelPlateaus, LabelPlateauFit.h): a
//     ball's pole that almost reaches the next layer was half a voxel off, beyond both filters' reach.
//  2d. The curvature step corrects in proportion to the bend; what is left grows as its square (a
//     ball of R voxels still lay about 1.15 / R^2 voxel inside: 3.5 % of its volume at R = 4.5).
//     psi <- psi - kBendShift u b |b|, with b the bend measured before the caps, after step 2e
//     and not where it found sharp edges (the sharpening's plane fits took a third longer on the
//     shifted psi, and its planes are right as they are) (shiftByBend).
//  2e. Where the label has flat faces meeting at sharp edges and corners, psi near them becomes the
//     distance to the faces' planes (sharpenLabelEdges, LabelEdgeSharpening.h): both filters round
//     an edge by about a voxel and bulge the faces beside it.
//  3. Each voxel edge between two labels gets the crossing of the two labels' psi along it, each
//     weighted by how deep its label reaches there within the filter's reach (near a thin part
//     of L, the filter mixes both of its sides: the other label tells better), and log w is the
//     least-squares fit of log(w_a / w_b) = log(t / (1 - t)) over these edges, held to the
//     voxel's own psi.
//  4. Pieces of a label a few voxels across keep their voxel volume (keepSmallPieceVolumes).
namespace omesh
{
namespace
{
constexpr double kFar = 1e30; // "no seed" in the distance transform

/// d[p] = min over seeds q (f[q] < kFar) of f[q] + w (p - q)^2, for p, q in [0, n): the lower
/// envelope of parabolas (Felzenszwalb and Huttenlocher 2012). v, z: scratch of n and n + 1.
void distanceTransform1D(const double* f, double* d, int n, double w, int* v, double* z)
{
  int k = -1;
  auto meet = [&](int p, int q) { return ((f[q] + w * q * q) - (f[p] + w * p * p)) / (2.0 * w * (q - p)); };
  for (int q = 0; q < n; ++q)
  {
    if (f[q] >= kFar)
      continue;
    double s = -std::numeric_limits<double>::infinity();
    while (k >= 0 && (s = meet(v[k], q)) <= z[k])
      --k;
    if (k < 0)
      s = -std::numeric_limits<double>::infinity();
    ++k;
    v[k] = q;
    z[k] = s;
    z[k + 1] = std::numeric_limits<double>::infinity();
  }
  if (k < 0)
  {
    std::fill(d, d + n, kFar);
    return;
  }
  k = 0;
  for (int q = 0; q < n; ++q)
  {
    while (z[k + 1] < q)
      ++k;
    d[q] = w * (q - v[k]) * (q - v[k]) + f[v[k]];
  }
}

/// Box b (lo[0] = INT_MAX: empty) grown to hold the voxels from lo to hi (both included).
void growBox(VoxelBox& b, const std::array<int, 3>& lo, const std::array<int, 3>& hi)
{
  if (b.lo[0] == std::numeric_limits<int>::max())
  {
    b.lo = lo;
    b.hi = hi;
    return;
  }
  for (int a = 0; a < 3; ++a)
  {
    b.lo[a] = std::min(b.lo[a], lo[a]);
    b.hi[a] = std::max(b.hi[a], hi[a]);
  }
}

/// The squared distance from every voxel centre of the box to the nearest seed's, in world units.
void squaredDistances(const VoxelBox& box, const std::vector<uint8_t>& seed, const std::array<double, 3>& h,
  std::vector<float>& out)
{
  out.resize(box.size);
  for (size_t i = 0; i < box.size; ++i)
    out[i] = seed[i] ? 0.0f : static_cast<float>(kFar);
  for (int axis = 0; axis < 3; ++axis)
    forEachLine(box, axis, [&](size_t start, size_t stride, int n, LineScratch& s) {
      for (int q = 0; q < n; ++q)
        s.a[q] = out[start + stride * q] >= 1e29f ? kFar : out[start + stride * q];
      distanceTransform1D(s.a.data(), s.b.data(), n, h[axis] * h[axis], s.v.data(), s.z.data());
      for (int q = 0; q < n; ++q)
        out[start + stride * q] = static_cast<float>(std::min(s.b[q], kFar));
    });
}

/// One filter round: psi <- G * psi - sum_a (var_a / 2) D_aa (G * psi) (indices clamped at the
/// box's faces).
class QuadraticPreservingFilter
{
public:
  QuadraticPreservingFilter(const std::array<double, 3>& sigmas, const std::array<double, 3>& h)
    : h_(h)
  {
    for (int a = 0; a < 3; ++a)
    {
      const double sigma = sigmas[a];
      const int r = std::clamp(static_cast<int>(std::ceil(3.0 * sigma / h[a])), 1, 31); // (31: the scratch's padding)
      std::vector<double>& k = kernel_[a];
      k.resize(2 * r + 1);
      double sum = 0.0, moment = 0.0;
      for (int i = -r; i <= r; ++i)
        sum += (k[i + r] = std::exp(-0.5 * (i * h[a]) * (i * h[a]) / (sigma * sigma)));
      for (int i = -r; i <= r; ++i)
        moment += (k[i + r] /= sum) * (i * h[a]) * (i * h[a]);
      halfVariance_[a] = 0.5 * moment; // the sampled kernel's own variance: quadratics exactly
    }
  }

  void apply(const VoxelBox& box, std::vector<float>& psi, std::vector<float>& tmp) const
  {
    for (int axis = 0; axis < 3; ++axis) // psi -> smoothed, in place through a padded line buffer
    {
      const std::vector<double>& k = kernel_[axis];
      const int r = static_cast<int>(k.size() / 2);
      forEachLine(box, axis, [&](size_t start, size_t stride, int n, LineScratch& s) {
        double* line = s.a.data() + r; // line[-r .. n - 1 + r], the ends repeated
        for (int q = 0; q < n; ++q)
          line[q] = psi[start + stride * q];
        for (int i = 1; i <= r; ++i)
        {
          line[-i] = line[0];
          line[n - 1 + i] = line[n - 1];
        }
        for (int q = 0; q < n; ++q)
        {
          double sum = 0.0;
          for (int i = 0; i <= 2 * r; ++i)
            sum += k[i] * line[q - r + i];
          psi[start + stride * q] = static_cast<float>(sum);
        }
      });
    }
    subtractLaplacian(box, psi, tmp, halfVariance_);
    psi.swap(tmp);
  }

  /// out = psi - sum_a c_a * (second difference of psi along a) / h_a^2 (indices clamped).
  void subtractLaplacian(
    const VoxelBox& box, const std::vector<float>& psi, std::vector<float>& out, const std::array<double, 3>& c) const
  {
    out.resize(box.size);
    const double w[3] = { c[0] / (h_[0] * h_[0]), c[1] / (h_[1] * h_[1]), c[2] / (h_[2] * h_[2]) };
    tbb::parallel_for(tbb::blocked_range<int>(0, box.n[2]), [&](const tbb::blocked_range<int>& slices) {
      for (int z = slices.begin(); z < slices.end(); ++z)
        for (int y = 0; y < box.n[1]; ++y)
          for (int x = 0; x < box.n[0]; ++x)
          {
            const int p[3] = { x, y, z };
            const size_t o = box.stride[1] * y + box.stride[2] * z + x;
            double lap = 0.0;
            for (int a = 0; a < 3; ++a)
            {
              const size_t down = p[a] > 0 ? o - box.stride[a] : o;
              const size_t up = p[a] + 1 < box.n[a] ? o + box.stride[a] : o;
              lap += w[a] * (static_cast<double>(psi[up]) - 2.0 * psi[o] + psi[down]);
            }
            out[o] = static_cast<float>(psi[o] - lap);
          }
    });
  }

private:
  std::array<double, 3> h_;
  std::array<std::vector<double>, 3> kernel_;
  std::array<double, 3> halfVariance_{};
};

/// Boundary voxels (a differently labelled voxel among their 26 neighbours), in increasing order:
/// slabs of z in parallel, concatenated in order.
std::vector<size_t> findBoundary(const std::array<int, 3>& dims, const std::vector<uint16_t>& index)
{
  const size_t sy = static_cast<size_t>(dims[0]), sz = sy * dims[1];
  const size_t slabs = chunkCount(static_cast<size_t>(dims[2]), 2);
  std::vector<std::vector<size_t>> found(slabs);
  forEachChunk(static_cast<size_t>(dims[2]), slabs, [&](size_t slab, size_t zBegin, size_t zEnd) {
    for (int z = static_cast<int>(zBegin); z < static_cast<int>(zEnd); ++z)
      for (int y = 0; y < dims[1]; ++y)
        for (int x = 0; x < dims[0]; ++x)
        {
          const size_t v = x + sy * y + sz * z;
          const uint16_t own = index[v];
          bool mixed = false;
          for (int dz = std::max(z - 1, 0); dz <= std::min(z + 1, dims[2] - 1) && !mixed; ++dz)
            for (int dy = std::max(y - 1, 0); dy <= std::min(y + 1, dims[1] - 1) && !mixed; ++dy)
            {
              const uint16_t* row = index.data() + sy * dy + sz * dz;
              for (int dx = std::max(x - 1, 0); dx <= std::min(x + 1, dims[0] - 1); ++dx)
                mixed = mixed || row[dx] != own;
            }
          if (mixed)
            found[slab].push_back(v);
        }
  });
  std::vector<size_t> boundary;
  for (const std::vector<size_t>& slab : found)
    boundary.insert(boundary.end(), slab.begin(), slab.end());
  return boundary;
}

constexpr uint32_t kWholeLabel = UINT32_MAX; ///< EstimatePass::piece: the label's small pieces

/// One smooth estimate: of a large piece of a label alone (where the label has more than one), or
/// of a label's other pieces together with all its voxels inside; its box and its boundary voxels
/// (indices into the boundary list).
struct EstimatePass
{
  int label;
  uint32_t piece;
  VoxelBox box;
  std::vector<uint32_t> own;
};

/// The estimates to make and the boundary voxels each speaks for; boxes grown by `reach`.
std::vector<EstimatePass> planPasses(const std::array<int, 3>& dims, const LabelPieces& pieces, int labelCount,
  const std::vector<size_t>& boundary, int reach, int pieceVoxels)
{
  std::vector<size_t> piecesOfLabel(static_cast<size_t>(std::max(labelCount, 0)), 0);
  for (uint32_t p = 0; p < pieces.count(); ++p)
    ++piecesOfLabel[pieces.label(p)];
  std::vector<EstimatePass> passes;
  std::vector<uint32_t> passOfPiece(pieces.count()), labelPass(piecesOfLabel.size(), UINT32_MAX);
  VoxelBox empty;
  empty.lo[0] = std::numeric_limits<int>::max();
  for (uint32_t p = 0; p < pieces.count(); ++p)
  {
    const int label = pieces.label(p);
    if (piecesOfLabel[label] > 1 && pieceVoxels > 0 && pieces.voxels(p) >= static_cast<size_t>(pieceVoxels))
    {
      passOfPiece[p] = static_cast<uint32_t>(passes.size());
      passes.push_back({ label, p, empty, {} });
      continue;
    }
    if (labelPass[label] == UINT32_MAX)
    {
      labelPass[label] = static_cast<uint32_t>(passes.size());
      passes.push_back({ label, kWholeLabel, empty, {} });
    }
    passOfPiece[p] = labelPass[label];
  }
  const size_t sy = static_cast<size_t>(dims[0]), sz = sy * dims[1];
  for (size_t bi = 0; bi < boundary.size(); ++bi)
  {
    const size_t v = boundary[bi];
    EstimatePass& pass = passes[passOfPiece[pieces.at(v)]];
    const std::array<int, 3> p{ static_cast<int>(v % sy), static_cast<int>((v / sy) % dims[1]), static_cast<int>(v / sz) };
    growBox(pass.box, p, p);
    pass.own.push_back(static_cast<uint32_t>(bi));
  }
  passes.erase(std::remove_if(passes.begin(), passes.end(), [](const EstimatePass& e) { return e.own.empty(); }),
    passes.end());
  for (EstimatePass& pass : passes)
  {
    for (int a = 0; a < 3; ++a) // the neighbours across the boundary, and the filter's reach
    {
      pass.box.lo[a] = std::max(pass.box.lo[a] - 1 - reach, 0);
      pass.box.hi[a] = std::min(pass.box.hi[a] + 2 + reach, dims[a]);
    }
    pass.box.finish();
  }
  return passes;
}

/// What the labels say about each boundary voxel: per direction (+x, -x, +y, -y, +z, -z) the
/// weighted sum of crossing estimates t (from this voxel, along that edge, by this voxel's own
/// label) and their weights; and the voxel's own psi (log, and the weight it gets in the fit).
struct Crossings
{
  explicit Crossings(size_t m, double neutral)
    : tSum(6 * m, 0.0f)
    , tWeight(6 * m, 0.0f)
    , prior(m, static_cast<float>(neutral))
    , priorWeight(m, static_cast<float>(kPinnedPriorWeight))
  {
  }
  static constexpr double kPriorWeight = 0.1;         ///< against 1 per edge: it fixes the scale only
  static constexpr double kPinnedPriorWeight = 0.001; ///< a voxel pinned to delta: its psi says little
  std::vector<float> tSum, tWeight, prior, priorWeight;
};

/// One label's (or piece's) smooth signed distance and what it says about the crossings of its
/// voxels' edges.
class LabelField
{
public:
  LabelField(const std::array<int, 3>& dims, const std::vector<uint16_t>& index, const LabelPieces& pieces,
    const std::array<double, 3>& h, const LabelSmoothingOptions& options)
    : dims_(dims)
    , index_(index)
    , pieces_(pieces)
    , h_(h)
    , hMin_(std::min({ h[0], h[1], h[2] }))
    , hMax_(std::max({ h[0], h[1], h[2] }))
    , sigma_(options.sigma * hMax_) // in world units along the coarsest axis
    , delta_(0.01 * hMin_)
    , rounds_(options.iterations)
    , sharpEdges_(options.sharpEdges)
    , fitPlateaus_(options.fitPlateaus)
    , wideSigma_(options.wideSigma > options.sigma ? options.wideSigma * hMax_ : 0.0)
    , filter_(sigmas(options.sigma, h), h)
    , wideFilter_(sigmas(wideSigma_ > 0 ? options.wideSigma : options.sigma, h), h)
  {
  }

  double hMin() const { return hMin_; }
  /// The narrow filter's reach in voxels (reachOf).
  int reach() const { return reachOf(sigma_); }
  /// The reach of the wider filter where there is one (the box must hold it), else reach().
  int boxReach() const { return std::max(reach(), reachOf(wideSigma_)); }

  /// The filter's width per axis: `sigma` voxels of that axis (the staircase a voxel leaves is as
  /// long as the voxel; on a CT grid of 0.5 x 0.5 x 1.25 one width in world units blurred the
  /// fine axes for the coarse one's sake).
  static std::array<double, 3> sigmas(double sigma, const std::array<double, 3>& h)
  {
    return { sigma * h[0], sigma * h[1], sigma * h[2] };
  }

  /// Steps 1 and 2 for the pass's piece (or label) in its box, and step 3's input from it: for
  /// each of its boundary voxels (`pass.own`: indices into `boundary`), the crossings of its edges
  /// to other labels and its own psi. `progress(fraction of the box)` after each round.
  template <class Progress>
  void run(const EstimatePass& pass, const std::vector<size_t>& boundary, Crossings& out, Progress&& progress)
  {
    const VoxelBox& box = pass.box;
    const std::vector<uint32_t>& own = pass.own;
    if (pass.piece != kWholeLabel)
      pieces_.fill(box, pass.piece, inside_);
    else
      fillLabel(box, pass.label);
    squaredDistances(box, inside_, h_, tmp_); // to the label's centres
    for (uint8_t& i : inside_)
      i = !i;
    squaredDistances(box, inside_, h_, psi_); // to the others'
    for (uint8_t& i : inside_)
      i = !i;
    forEachVoxel(box.size, [this](size_t i) {
      psi_[i] = static_cast<float>(inside_[i] ? std::sqrt(psi_[i]) - 0.5 * hMin_ : -(std::sqrt(tmp_[i]) - 0.5 * hMin_));
    });
    // how deep the label reaches near each of its boundary voxels: the largest distance inside
    // it within the filter's reach
    tmp_ = psi_;
    runningMaximum(box, reach(), tmp_);
    depth_.resize(own.size());
    for (size_t i = 0; i < own.size(); ++i)
      depth_[i] = tmp_[offsetOf(box, boundary[own[i]])];
    const int passes = wideSigma_ > 0 ? 2 : 1;
    if (passes == 2)
      wide_ = psi_;
    smooth(box, filter_, psi_, [&](double f) { progress(f / passes); });
    if (passes == 2)
    {
      psi_.swap(wide_);
      smooth(box, wideFilter_, psi_, [&](double f) { progress(0.5 + 0.5 * f); });
      psi_.swap(wide_);
      blendWide(box);
    }
    measureBend(box);
    if (fitPlateaus_)
      fitLabelPlateaus(box, h_, psi_, inside_, [&](size_t o) { return index_[globalOf(box, o)]; }, delta_);
    if (sharpEdges_)
    {
      wide_ = psi_; // what the sharpening leaves as it is gets the bend step
      sharpenLabelEdges(box, h_, psi_, inside_, delta_, tmp_);
    }
    shiftByBend(sharpEdges_ ? &wide_ : nullptr);
    collect(box, boundary, own, out);
    progress(1.0);
  }

  /// Step 2 with `filter` on `psi` (psi_ itself or a box of the same size); `progress(fraction)`
  /// after each round.
  template <class Progress>
  void smooth(const VoxelBox& box, const QuadraticPreservingFilter& filter, std::vector<float>& psi, Progress&& progress)
  {
    psi_.swap(psi);
    for (int round = 0; round < rounds_; ++round)
    {
      filter.apply(box, psi_, tmp_);
      constrain();
      progress((round + 1.0) / (rounds_ + 1.0));
    }
    filter.subtractLaplacian(box, psi_, tmp_,
      { kCurvatureShift * h_[0] * h_[0], kCurvatureShift * h_[1] * h_[1], kCurvatureShift * h_[2] * h_[2] });
    psi_.swap(tmp_);
    constrain();
    psi_.swap(psi);
  }

  /// psi_ (the narrow filter's) blended towards wide_ (the wide one's) where the narrow one's zero
  /// set bends little nearby: its curvature (the sum of the principal ones, |Laplacian psi|, per
  /// coarsest voxel) within kBlendReach of the wide filter's reach below kFlatCurvature, the wide
  /// one alone; above kBentCurvature the narrow one alone. Both keep the sign constraint, so does
  /// any blend of them.
  void blendWide(const VoxelBox& box)
  {
    filter_.subtractLaplacian(box, psi_, tmp_, { -1.0, -1.0, -1.0 }); // psi + Laplacian psi
    const double band = hMax_;
    forEachVoxel(box.size, [&](size_t i) {
      tmp_[i] = std::abs(psi_[i]) <= band ? static_cast<float>(std::abs(tmp_[i] - psi_[i]) * hMax_) : 0.0f;
    });
    runningMaximum(box, static_cast<int>(std::ceil(kBlendReach * reachOf(wideSigma_))), tmp_);
    forEachVoxel(box.size, [&](size_t i) {
      const double a = std::clamp((kBentCurvature - tmp_[i]) / (kBentCurvature - kFlatCurvature), 0.0, 1.0);
      psi_[i] = static_cast<float>((1.0 - a) * psi_[i] + a * wide_[i]);
    });
  }

  /// bend_ = the curvature the filters left (Laplacian psi, per bendUnit()), clamped at
  /// kBendClamp: read before the caps, whose rims would read as bends; 0 on the box's faces, where
  /// a one-sided second difference reads the filters' repeated ends as a bend (planes reaching the
  /// image's side moved by 0.1 voxel).
  void measureBend(const VoxelBox& box)
  {
    const double u = bendUnit();
    filter_.subtractLaplacian(box, psi_, bend_, { -1.0, -1.0, -1.0 }); // psi + Laplacian psi
    forEachVoxel(box.size, [&](size_t i) {
      int p[3];
      box.coordinates(i, p);
      const bool face = p[0] == 0 || p[1] == 0 || p[2] == 0 || p[0] + 1 == box.n[0] || p[1] + 1 == box.n[1] || p[2] + 1 == box.n[2];
      bend_[i] = face ? 0.0f : static_cast<float>(std::clamp((bend_[i] - psi_[i]) * u, -kBendClamp, kBendClamp));
    });
  }

  /// Step 2d: psi <- psi - kBendShift u b |b| (b = bend_), then the sign constraint again; not
  /// where psi differs from `unsharpened` (given: psi before step 2e, whose planes it keeps).
  void shiftByBend(const std::vector<float>* unsharpened)
  {
    const double g = kBendShift * bendUnit();
    forEachVoxel(psi_.size(), [&](size_t i) {
      if (!unsharpened || (*unsharpened)[i] == psi_[i])
        psi_[i] = static_cast<float>(psi_[i] - g * bend_[i] * std::abs(bend_[i]));
    });
    constrain();
  }

  /// The length the bend is measured in: between the finest and the coarsest axis (on a CT grid
  /// of 0.5 x 0.5 x 1.25, either end over- or under-corrected its balls).
  double bendUnit() const { return std::sqrt(hMin_ * hMax_); }

private:
  /// A filter's reach in voxels (of every axis): the truncated Gaussian's and one more.
  int reachOf(double sigma) const { return 1 + static_cast<int>(std::ceil(3.0 * sigma / hMax_)); }

  /// inside_: the box's voxels of `label`.
  void fillLabel(const VoxelBox& box, int label)
  {
    const size_t sy = static_cast<size_t>(dims_[0]), sz = sy * dims_[1];
    inside_.resize(box.size);
    const size_t slices = static_cast<size_t>(box.n[2]);
    forEachChunk(slices, chunkCount(slices, 2), [&](size_t, size_t zBegin, size_t zEnd) {
      for (int z = static_cast<int>(zBegin); z < static_cast<int>(zEnd); ++z)
        for (int y = 0; y < box.n[1]; ++y)
        {
          const uint16_t* row = index_.data() + box.lo[0] + sy * (box.lo[1] + y) + sz * (box.lo[2] + z);
          uint8_t* in = inside_.data() + box.stride[1] * y + box.stride[2] * z;
          for (int x = 0; x < box.n[0]; ++x)
            in[x] = row[x] == label;
        }
    });
  }

  /// The image index of the box's voxel at offset o.
  size_t globalOf(const VoxelBox& box, size_t o) const
  {
    int p[3];
    box.coordinates(o, p);
    return static_cast<size_t>(p[0] + box.lo[0]) +
      static_cast<size_t>(dims_[0]) * (static_cast<size_t>(p[1] + box.lo[1]) + static_cast<size_t>(dims_[1]) * (p[2] + box.lo[2]));
  }

  size_t offsetOf(const VoxelBox& box, size_t v) const
  {
    const size_t sy = static_cast<size_t>(dims_[0]), sz = sy * dims_[1];
    const int p[3] = { static_cast<int>(v % sy), static_cast<int>((v / sy) % dims_[1]), static_cast<int>(v / sz) };
    return box.offset(p);
  }

  /// psi at least delta inside the label, at most -delta outside: the zero set between the centres.
  void constrain()
  {
    const float d = static_cast<float>(delta_);
    forEachVoxel(psi_.size(), [this, d](size_t i) { psi_[i] = inside_[i] ? std::max(psi_[i], d) : std::min(psi_[i], -d); });
  }

  void collect(const VoxelBox& box, const std::vector<size_t>& boundary, const std::vector<uint32_t>& own,
    Crossings& out) const
  {
    const size_t strides[3] = { 1, static_cast<size_t>(dims_[0]), static_cast<size_t>(dims_[0]) * dims_[1] };
    const double pinned = 1.000001 * delta_;
    // each boundary voxel is written by its own label's pass only: the voxels in parallel
    forEachVoxel(own.size(), [&](size_t i) {
      const uint32_t bi = own[i];
      const size_t v = boundary[bi];
      const int p[3] = { static_cast<int>(v % strides[1]), static_cast<int>((v / strides[1]) % dims_[1]),
        static_cast<int>(v / strides[2]) };
      const size_t o = box.offset(p);
      const double deep = depth_[i] / (kDeepReach * sigma_); // a thin part's psi says little
      const double depthTrust = std::clamp(deep * deep, 0.01, 1.0);
      if (psi_[o] > pinned)
      {
        out.prior[bi] = static_cast<float>(std::log(psi_[o]));
        out.priorWeight[bi] = static_cast<float>(std::max(Crossings::kPriorWeight * std::min(deep * deep, 1.0),
          Crossings::kPinnedPriorWeight));
      }
      for (int a = 0; a < 3; ++a)
        for (int side = 0; side < 2; ++side) // +a, then -a
        {
          const int q = p[a] + (side ? -1 : 1);
          if (q < box.lo[a] || q >= box.hi[a])
            continue;
          const size_t u = side ? v - strides[a] : v + strides[a];
          if (index_[u] == index_[v])
            continue;
          const double pa = psi_[o], pb = psi_[side ? o - box.stride[a] : o + box.stride[a]];
          const double trust = (std::abs(pa) <= pinned || std::abs(pb) <= pinned ? 0.05 : 1.0) * depthTrust;
          out.tSum[6 * bi + 2 * a + side] += static_cast<float>(trust * pa / (pa - pb));
          out.tWeight[6 * bi + 2 * a + side] += static_cast<float>(trust);
        }
    });
  }

  /// beta: a staircase distance's zero set lies about beta h^2 times the mean curvature (1 / R on
  /// a sphere) towards the convex side; fitted on spheres of radius 4.5 to 10 voxels.
  static constexpr double kCurvatureShift = 0.15;
  /// Step 2d: after the curvature step a ball's zero set still lay about 1.15 / R^2 voxel inside
  /// (R in voxels: 0.072 at R = 3.5, 0.007 at R = 14), 0.29 times the squared bend; 0.22 leaves
  /// balls of radius 3.5 to 14 within 0.4 % of their volume on average (fitted on 12 placements
  /// each, with the shells and the CT grid's balls). kBendClamp: a ball of radius 3 per bendUnit();
  /// sharper bends are edges and corners (step 2e's).
  static constexpr double kBendShift = 0.22;
  static constexpr double kBendClamp = 0.67;
  /// Depth (largest psi within the filter's reach) at which a label's crossings count fully, in sigmas.
  static constexpr double kDeepReach = 4.0;
  /// blendWide: the wide filter alone where the narrow one's zero set bends less than this nearby
  /// (the sum of the principal curvatures, per coarsest voxel: a ball of 2.5 voxels' radius), the
  /// narrow one alone from kBentCurvature (1.7 voxels; a box's edge is sharper), within this share
  /// of the wide filter's reach. Fitted on balls of radius 3.5 to 14 voxels, shells 1.5 and 2 voxels
  /// thick and tilted boxes (Benchmarks/label_fidelity.py).
  static constexpr double kFlatCurvature = 0.8;
  static constexpr double kBentCurvature = 1.2;
  static constexpr double kBlendReach = 0.6;

  const std::array<int, 3>& dims_;
  const std::vector<uint16_t>& index_;
  const LabelPieces& pieces_;
  std::array<double, 3> h_;
  double hMin_, hMax_, sigma_, delta_;
  int rounds_;
  bool sharpEdges_;
  bool fitPlateaus_;
  double wideSigma_; ///< 0: no wide filter
  QuadraticPreservingFilter filter_, wideFilter_;
  std::vector<uint8_t> inside_;
  std::vector<float> psi_, tmp_, depth_, wide_, bend_;
};

/// Step 3: log w by least squares, per edge log w_a - log w_b = log(t / (1 - t)) (t from a, both
/// labels' estimates together), each voxel held to its prior. Gauss-Seidel sweeps (the edges tie
/// neighbours; a few dozen sweeps settle them).
std::vector<double> fitLogWeights(const std::array<int, 3>& dims, const std::vector<size_t>& boundary,
  Crossings& c)
{
  const size_t m = boundary.size();
  const size_t strides[3] = { 1, static_cast<size_t>(dims[0]), static_cast<size_t>(dims[0]) * dims[1] };
  std::vector<int64_t> neighbour(6 * m, -1);
  std::vector<float> target(6 * m, 0.0f);
  for (size_t bi = 0; bi < m; ++bi)
    for (int a = 0; a < 3; ++a)
    {
      const size_t forward = 6 * bi + 2 * a;
      if (c.tWeight[forward] <= 0.0f) // no edge to another label there (or past the grid's side)
        continue;
      const size_t bj = static_cast<size_t>(
        std::lower_bound(boundary.begin(), boundary.end(), boundary[bi] + strides[a]) - boundary.begin());
      if (bj >= m || boundary[bj] != boundary[bi] + strides[a])
        continue;
      const size_t backward = 6 * bj + 2 * a + 1; // the other voxel's estimate, from its end
      const double sum = c.tSum[forward] + (c.tWeight[backward] - c.tSum[backward]);
      const double t = std::clamp(sum / (c.tWeight[forward] + c.tWeight[backward]), 0.01, 0.99); // in the band
      const double logRatio = std::log(t / (1.0 - t));
      neighbour[forward] = static_cast<int64_t>(bj);
      target[forward] = static_cast<float>(logRatio);
      neighbour[backward] = static_cast<int64_t>(bi);
      target[backward] = static_cast<float>(-logRatio);
    }
  std::vector<float>().swap(c.tSum);
  std::vector<float>().swap(c.tWeight);
  std::vector<double> x(c.prior.begin(), c.prior.end());
  for (int sweep = 0; sweep < 60; ++sweep)
  {
    double change = 0.0;
    for (size_t bi = 0; bi < m; ++bi)
    {
      double num = static_cast<double>(c.priorWeight[bi]) * c.prior[bi], den = c.priorWeight[bi];
      for (int e = 0; e < 6; ++e)
        if (neighbour[6 * bi + e] >= 0)
        {
          num += x[neighbour[6 * bi + e]] + target[6 * bi + e];
          den += 1.0;
        }
      change = std::max(change, std::abs(num / den - x[bi]));
      x[bi] = num / den;
    }
    if (change < 1e-6)
      break;
  }
  return x;
}
}

std::vector<float> labelInterfaceWeights(const std::array<int, 3>& dims, const std::vector<uint16_t>& index,
  int labelCount, const std::array<double, 3>& spacing, const LabelSmoothingOptions& options)
{
  std::vector<float> weights(index.size(), 1.0f);
  std::vector<size_t> boundary = findBoundary(dims, index);
  if (boundary.empty())
    return weights;

  const LabelPieces pieces(dims, index);
  LabelField field(dims, index, pieces, spacing, options);
  std::vector<EstimatePass> passes = planPasses(dims, pieces, labelCount, boundary, field.boxReach(), options.pieceVoxels);
  double work = 0.0;
  for (const EstimatePass& pass : passes)
    work += static_cast<double>(pass.box.size);
  Crossings crossings(boundary.size(), std::log(0.5 * field.hMin()));
  double done = 0.0;
  for (EstimatePass& pass : passes)
  {
    field.run(pass, boundary, crossings, [&](double fraction) {
      if (options.progress && !options.progress(0.95 * (done + fraction * pass.box.size) / work))
        throw LabelSmoothingAborted();
    });
    done += static_cast<double>(pass.box.size);
    std::vector<uint32_t>().swap(pass.own);
  }
  const std::vector<double> x = fitLogWeights(dims, boundary, crossings);
  for (size_t bi = 0; bi < boundary.size(); ++bi)
    weights[boundary[bi]] = static_cast<float>(std::exp(x[bi]) / field.hMin());
  std::vector<size_t>().swap(boundary);
  keepSmallPieceVolumes(dims, index, weights, options.smallPieceVoxels, [&](double fraction) {
    return !options.progress || options.progress(0.95 + 0.05 * fraction);
  });
  if (options.progress && !options.progress(1.0))
    throw LabelSmoothingAborted();
  return weights;
}
}
