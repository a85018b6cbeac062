// SPDX-License-Identifier: GPL-3.0-or-later
#include "SmallPieceVolumes.h"

#include "LabelSmoothing.h"
#include "VoxelCorners.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>

namespace omesh
{
namespace
{
constexpr int kSamples = 4; ///< per axis and cell of voxel centres
constexpr int kPerCell = kSamples * kSamples * kSamples;

/// A sample's place in its stratum along one axis, in [0, 1): fixed per cell, sample and axis (a
/// hash). Samples at the strata's centres would put an axis-aligned face exactly between two rows
/// of them: the sampled volume would then jump by a quarter voxel's layer at once as the factor
/// moves the face, and the factor found overshoot by up to that.
double jitter(size_t cell, int sample, int axis)
{
  uint64_t z = (static_cast<uint64_t>(cell) * kPerCell + static_cast<uint64_t>(sample)) * 3 + static_cast<uint64_t>(axis);
  z += 0x9e3779b97f4a7c15ull; // splitmix64
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  z ^= z >> 31;
  return static_cast<double>(z >> 11) * 0x1.0p-53;
}
constexpr int kRounds = 3;  ///< of corrections over all small pieces
/// The smooth volume stays where it is within this many of the count's standard deviations.
constexpr double kTolerance = 1.0;
/// A piece of at least kThinVoxels with fewer interior voxels (all 26 neighbours its own) than
/// kThinShare of them is thin everywhere (a shell, a plate): its count is off by up to half a voxel
/// at nearly every voxel and its smooth volume is the closer one (shells 1.5 voxels thick: 0.5 %
/// against the count's 1.3 %). A smaller one is a speck a few voxels across, whose corners are all
/// there is of it: it keeps its count.
constexpr double kThinShare = 0.1;
constexpr size_t kThinVoxels = 500;

enum : uint8_t
{
  kUnseen = 0,
  kQueued = 1,
  kLarge = 2, ///< in a piece too large, or touching the border
  kDone = 3
};

/// One piece of a label: its voxels, and the cells of voxel centres with a corner among them.
class Piece
{
public:
  Piece(const std::array<int, 3>& dims, const std::vector<uint16_t>& index, std::vector<float>& weights)
    : dims_(dims)
    , index_(index)
    , weights_(weights)
  {
  }

  /// Grows the piece of voxel `seed` over `state`; false when it has more than `maxVoxels`
  /// voxels, touches the border or meets a voxel already known to lie in a large piece (then
  /// every voxel it reached is marked kLarge).
  bool grow(size_t seed, int maxVoxels, std::vector<uint8_t>& state)
  {
    voxels_.assign(1, seed);
    state[seed] = kQueued;
    bool small = true;
    for (size_t next = 0; next < voxels_.size() && small; ++next)
    {
      int p[3];
      coordinates(voxels_[next], p);
      if (p[0] == 0 || p[1] == 0 || p[2] == 0 || p[0] == dims_[0] - 1 || p[1] == dims_[1] - 1 || p[2] == dims_[2] - 1)
        small = false;
      for (int n = 0; n < 27 && small; ++n)
      {
        const size_t u = offset(p[0] + n % 3 - 1, p[1] + (n / 3) % 3 - 1, p[2] + n / 9 - 1);
        if (index_[u] != index_[seed] || state[u] == kQueued)
          continue;
        if (state[u] == kLarge)
          small = false;
        else
        {
          state[u] = kQueued;
          voxels_.push_back(u);
          small = voxels_.size() <= static_cast<size_t>(maxVoxels);
        }
      }
    }
    for (size_t v : voxels_)
      state[v] = small ? kDone : kLarge;
    return small;
  }

  /// The voxels grow() found.
  const std::vector<size_t>& voxels() const { return voxels_; }

  /// Scales the weights of the piece of `voxels` so that its volume is its voxel count's (see
  /// keepSmallPieceVolumes): the factor found from every sample's threshold at once.
  void keepVolume(const std::vector<size_t>& voxels)
  {
    voxels_ = voxels;
    listCells();
    boundary_.clear();
    original_.clear();
    for (size_t v : voxels_)
      if (hasOtherNeighbour(v)) // a boundary voxel: its weight counts
      {
        boundary_.push_back(v);
        original_.push_back(weights_[v]);
      }
    if (voxels_.size() >= kThinVoxels &&
      static_cast<double>(voxels_.size() - boundary_.size()) < kThinShare * static_cast<double>(voxels_.size()))
      return;
    // each boundary voxel puts the count off by up to half a voxel either way (variance 1/12 of a
    // voxel): within kTolerance standard deviations of it the smooth volume stays as it is
    const double target = static_cast<double>(voxels_.size());
    thresholds();
    const double volume = whole_ + static_cast<double>(std::count_if(threshold_.begin(), threshold_.end(),
                                     [](double t) { return t < 1.0; })) / kPerCell;
    if (std::abs(volume - target) <= kTolerance * std::sqrt(static_cast<double>(boundary_.size()) / 12.0))
      return;
    // the factor that puts target - whole of the samples on the piece's side: between the k-th and
    // the (k+1)-th smallest threshold
    const long k = std::lround((target - whole_) * kPerCell);
    const long n = static_cast<long>(threshold_.size());
    double factor;
    if (k <= 0)
      factor = std::exp(-3.0);
    else if (k >= n)
      factor = std::exp(3.0);
    else
    {
      std::nth_element(threshold_.begin(), threshold_.begin() + k, threshold_.end());
      const double above = threshold_[static_cast<size_t>(k)];
      const double below = *std::max_element(threshold_.begin(), threshold_.begin() + k);
      factor = std::clamp(std::sqrt(below * above), std::exp(-3.0), std::exp(3.0));
    }
    for (size_t i = 0; i < boundary_.size(); ++i)
      weights_[boundary_[i]] = original_[i] * static_cast<float>(factor);
  }

private:
  void coordinates(size_t v, int p[3]) const
  {
    p[0] = static_cast<int>(v % static_cast<size_t>(dims_[0]));
    p[1] = static_cast<int>((v / static_cast<size_t>(dims_[0])) % static_cast<size_t>(dims_[1]));
    p[2] = static_cast<int>(v / (static_cast<size_t>(dims_[0]) * static_cast<size_t>(dims_[1])));
  }
  size_t offset(int x, int y, int z) const
  {
    return static_cast<size_t>(x) + static_cast<size_t>(dims_[0]) * (static_cast<size_t>(y) + static_cast<size_t>(dims_[1]) * static_cast<size_t>(z));
  }
  bool hasOtherNeighbour(size_t v) const
  {
    int p[3];
    coordinates(v, p);
    for (int n = 0; n < 27; ++n)
      if (index_[offset(p[0] + n % 3 - 1, p[1] + (n / 3) % 3 - 1, p[2] + n / 9 - 1)] != index_[v])
        return true;
    return false;
  }

  /// The lower corners of the cells with a corner in the piece (none at the border: grow() kept
  /// the piece one voxel away from it).
  void listCells()
  {
    cells_.clear();
    for (size_t v : voxels_)
    {
      int p[3];
      coordinates(v, p);
      for (int c = 0; c < 8; ++c)
        cells_.push_back(offset(p[0] - (c & 1), p[1] - ((c >> 1) & 1), p[2] - ((c >> 2) & 1)));
    }
    std::sort(cells_.begin(), cells_.end());
    cells_.erase(std::unique(cells_.begin(), cells_.end()), cells_.end());
  }

  /// For every sample point of the piece's mixed cells, the factor on the piece's weights above
  /// which its label wins there (the others' largest summed weight over its own: its corners in
  /// such a cell are all boundary voxels of the piece, scaled alike); whole_ gets the cells all of
  /// whose corners are the piece's.
  void thresholds()
  {
    const uint16_t label = index_[voxels_.front()];
    threshold_.clear();
    whole_ = 0.0;
    for (size_t cell : cells_)
    {
      int lo[3];
      coordinates(cell, lo);
      VoxelCorners k;
      loadCorners(dims_, index_.data(), weights_.data(), lo, k);
      if (k.uniform) // all eight corners in the piece (26-connected: one piece per label and cell)
      {
        whole_ += 1.0;
        continue;
      }
      distinctLabels(k);
      for (int s = 0; s < kPerCell; ++s)
      {
        const double f[3] = { (s % kSamples + jitter(cell, s, 0)) / kSamples,
          ((s / kSamples) % kSamples + jitter(cell, s, 1)) / kSamples,
          (s / (kSamples * kSamples) + jitter(cell, s, 2)) / kSamples };
        double sums[8];
        labelWeights(k, f, sums);
        double own, other;
        ownAndStrongestOther(k, sums, label, own, other);
        threshold_.push_back(own > 0.0 ? other / own : std::numeric_limits<double>::infinity());
      }
    }
  }

  const std::array<int, 3>& dims_;
  const std::vector<uint16_t>& index_;
  std::vector<float>& weights_;
  std::vector<size_t> voxels_, cells_, boundary_;
  std::vector<float> original_;
  std::vector<double> threshold_;
  double whole_ = 0.0;
};

/// Per piece, whether a voxel of another piece is among its voxels' 26 neighbours (the two share a
/// cell of voxel centres); pieces lie off the border, so every neighbour is in the grid.
std::vector<char> sharingPieces(const std::array<int, 3>& dims, const std::vector<std::vector<size_t>>& pieces)
{
  std::unordered_map<size_t, size_t> pieceOf;
  for (size_t i = 0; i < pieces.size(); ++i)
    for (size_t v : pieces[i])
      pieceOf.emplace(v, i);
  const long sy = dims[0], sz = static_cast<long>(dims[0]) * dims[1];
  std::vector<char> shares(pieces.size(), 0);
  for (size_t i = 0; i < pieces.size(); ++i)
    for (size_t v : pieces[i])
      for (int n = 0; n < 27 && !shares[i]; ++n)
      {
        const long u = static_cast<long>(v) + (n % 3 - 1) + sy * ((n / 3) % 3 - 1) + sz * (n / 9 - 1);
        const auto it = pieceOf.find(static_cast<size_t>(u));
        shares[i] = it != pieceOf.end() && it->second != i;
      }
  return shares;
}
}

void keepSmallPieceVolumes(const std::array<int, 3>& dims, const std::vector<uint16_t>& index,
  std::vector<float>& weights, int maxVoxels, const std::function<bool(double)>& progress)
{
  if (maxVoxels <= 0)
    return;
  std::vector<uint8_t> state(index.size(), kUnseen);
  const size_t slice = static_cast<size_t>(dims[0]) * static_cast<size_t>(dims[1]);
  Piece piece(dims, index, weights);
  std::vector<std::vector<size_t>> pieces;
  for (size_t v = 0; v < index.size(); ++v)
  {
    if (progress && v % slice == 0 && !progress(0.5 * static_cast<double>(v) / static_cast<double>(index.size())))
      throw LabelSmoothingAborted();
    // seeds: the voxels with a fitted weight (labelInterfaceWeights leaves 1 exactly on every
    // voxel away from other labels, and every piece has boundary voxels)
    if (weights[v] != 1.0f && state[v] == kUnseen && piece.grow(v, maxVoxels, state))
      pieces.push_back(piece.voxels());
  }
  std::vector<uint8_t>().swap(state);
  // pieces that share a cell (nested labels) trade volume: a few rounds settle them; the others
  // (isolated blobs, speckle) are done after one
  const std::vector<char> shares = sharingPieces(dims, pieces);
  for (int round = 0; round < kRounds; ++round)
    for (size_t i = 0; i < pieces.size(); ++i)
    {
      if (progress && !progress(0.5 + 0.5 * (round + static_cast<double>(i) / pieces.size()) / kRounds))
        throw LabelSmoothingAborted();
      if (round == 0 || shares[i])
        piece.keepVolume(pieces[i]);
    }
}
}
