// SPDX-License-Identifier: GPL-3.0-or-later
#include "DihedralImprovement.h"

#include "EdgeSplitter.h"
#include "InterfaceCollapse.h"
#include "ImprovementMesh.h"
#include "MeshQuality.h"
#include "ShapeSummary.h"
#include "SliverPeeler.h"
#include "TetFlips.h"
#include "VertexMover.h"
#include "WorkerThreads.h"

#include <algorithm>
#include <array>
#include <utility>
#include <vector>

namespace omesh
{
namespace
{
/// Raises the worst tetrahedra by flips and vertex moves (see improveDihedralAngles): rounds over
/// the bad tetrahedra, worst first, each given to the local changes in turn (flips, vertex moves,
/// peeling, edge splits, interface collapses) until one pays.
class DihedralImprover
{
public:
  DihedralImprover(TetMesh& mesh, const HierarchicalOracle& oracle, const DihedralImprovementOptions& options)
    : state_(mesh, oracle, options)
    , flips_(state_)
    , mover_(state_)
    , splitter_(state_, flips_, mover_)
    , peeler_(state_, flips_, mover_)
    , collapse_(state_)
  {
  }

  DihedralImprovementReport run()
  {
    DihedralImprovementReport& report = state_.report();
    const DihedralImprovementOptions& options = state_.options();
    state_.measure(report.outsideBefore, report.minBefore, report.maxBefore);
    // A tetrahedron keeps its quality until one of its vertices moves: after the first round only
    // the ones left bad and the ones made or moved since can be bad.
    std::vector<int> candidates(state_.stars().size());
    for (std::size_t t = 0; t < candidates.size(); ++t)
      candidates[t] = static_cast<int>(t);
    bool changed = true;
    for (int round = 0; round < options.rounds && changed; ++round)
    {
      changed = runRound(round, candidates);
      report.rounds = round + 1;
    }
    report.cutShort = changed && report.rounds == options.rounds && options.rounds > 0;
    state_.writeBack();
    state_.measure(report.outsideAfter, report.minAfter, report.maxAfter, &report.outsideHeld);
    return report;
  }

private:
  /// Works through the bad tetrahedra among `candidates`, worst first; leaves in `candidates` the
  /// ones to look at next round (those still there and bad, and those made or moved).
  bool runRound(int round, std::vector<int>& candidates)
  {
    std::vector<std::pair<double, int>> bad = badAmong(candidates);
    state_.touched().clear();
    bool changed = false;
    for (std::size_t k = 0; k < bad.size(); ++k)
    {
      if (state_.options().progress && (k & 63u) == 0)
        state_.options().progress((round + static_cast<double>(k) / bad.size()) / state_.options().rounds);
      const int t = bad[k].second;
      if (state_.stars().alive(t) && state_.quality(t) < 1.0)
        changed = improveTet(t) || changed;
    }
    candidates = std::move(state_.touched());
    for (const auto& entry : bad)
      candidates.push_back(entry.second);
    std::sort(candidates.begin(), candidates.end());
    candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
    return changed;
  }

  /// The bad tetrahedra among `candidates` with their quality, worst first. Judged in chunks on
  /// the threads runOnThreads allows (the first round judges every tetrahedron; reads only).
  std::vector<std::pair<double, int>> badAmong(const std::vector<int>& candidates) const
  {
    const std::size_t chunks = chunkCount(candidates.size(), kTetsPerChunk);
    std::vector<std::vector<std::pair<double, int>>> parts(chunks);
    forEachChunk(candidates.size(), chunks, [&](std::size_t k, std::size_t begin, std::size_t end) {
      for (std::size_t i = begin; i < end; ++i)
      {
        const int t = candidates[i];
        if (!state_.stars().alive(t))
          continue;
        const double q = state_.quality(t);
        if (q < 1.0)
          parts[k].emplace_back(q, t);
      }
    });
    std::vector<std::pair<double, int>> bad;
    for (const auto& part : parts)
      bad.insert(bad.end(), part.begin(), part.end());
    std::sort(bad.begin(), bad.end());
    return bad;
  }

  /// Gives bad tetrahedron t to the local changes in turn; true when one changed the mesh.
  bool improveTet(int t)
  {
    const auto q = state_.stars().tet(t);
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j)
        if (flips_.removeEdge(q[i], q[j]))
          return true;
    for (int f = 0; f < 4; ++f)
      if (flips_.removeFace(t, f))
        return true;
    bool moved = false;
    for (int v : q)
    {
      if (!state_.stars().alive(t) || state_.quality(t) >= 1.0)
        break;
      moved = mover_.moveVertex(v) || moved;
    }
    if (moved || !state_.stars().alive(t))
      return moved;
    if (peeler_.peel(t))
      return true;
    // the last resort, for tetrahedra whose vertices cannot move (a thin layer between two
    // interfaces, feature lines): a new interior vertex on one of its edges, longest first
    const auto& p = state_.mesh().points;
    std::array<std::pair<double, std::pair<int, int>>, 6> edges;
    int k = 0;
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j)
        edges[k++] = { -norm(p[static_cast<std::size_t>(q[i])] - p[static_cast<std::size_t>(q[j])]), { q[i], q[j] } };
    std::sort(edges.begin(), edges.end());
    for (const auto& e : edges)
      if (splitter_.splitEdge(e.second.first, e.second.second))
        return true;
    return collapse_.collapseAround(t);
  }

  ImprovementMesh state_;
  TetFlips flips_;
  VertexMover mover_;
  EdgeSplitter splitter_;
  SliverPeeler peeler_;
  InterfaceCollapse collapse_;
};
}

double dihedralWindowQuality(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, double minAngle,
  double maxAngle)
{
  double lo = 0.0, hi = 180.0;
  if (!dihedralAngleRange(a, b, c, d, lo, hi) || !(lo > 0))
    return -1.0;
  return std::min(lo / minAngle, (180.0 - hi) / (180.0 - maxAngle));
}

DihedralImprovementReport improveDihedralAngles(
  TetMesh& mesh, const HierarchicalOracle& oracle, const DihedralImprovementOptions& options)
{
  DihedralImprover improver(mesh, oracle, options);
  return improver.run();
}
}
