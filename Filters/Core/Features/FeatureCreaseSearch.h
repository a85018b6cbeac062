// SPDX-License-Identifier: GPL-3.0-or-later
// The last phase of the feature-line search (findFeatureLines): the creases of single inputs
// (Domain::creases: a box's edges, a cylinder's rims, a surface's sharp edges), kept where the input
// decides the material on its side and another material lies across. The grid search does not see
// them (one input's boundary, no regions meeting); where a crease passes into another input its end
// becomes a vertex of the curve found there, so that the lines meet instead of passing each other.
#pragma once

#include "Domain.h"
#include "FeatureCurveResampler.h"
#include "OracleFeatureLines.h"

#include <array>
#include <map>
#include <vector>

namespace omesh::featurelines
{
class FeatureCreaseSearch
{
public:
  /// `spacing`, `diagonal`: the grid search's (GridCrossings). The pieces are added to `result`
  /// through `resampler`, which added the curves found.
  FeatureCreaseSearch(const HierarchicalOracle& oracle, const FeatureLineOptions& options, double spacing,
    double diagonal, FeatureCurveResampler& resampler, FeatureLines& result);

  /// Each crease walked chord by chord, cut at the other inputs' crossings along it (exact for
  /// straight chords), each stretch probed beside its middle; runs of stretches seen with the same
  /// materials are the pieces. Ends where the crease passes into another input become vertices of
  /// the found curves there; the pieces are resampled as curves. Nothing when options.creaseAngle
  /// is 180.
  void addCreases();

private:
  /// A crease seen with one set of materials; an end that enters another input is `entering`;
  /// `across[end]`: the materials the crease is seen with beyond that end (empty: none, not seen).
  struct CreasePiece
  {
    std::vector<Vec3> points;
    std::vector<int> materials;
    bool closed = false;
    bool entering[2] = { false, false };
    std::vector<int> across[2];
    int endPoint[2] = { -1, -1 };
  };

  std::vector<int> seenAt(int owner, const Vec3& m, const Vec3& a, const Vec3& b, const std::array<Vec3, 2>& n) const;
  void visiblePieces(int owner, const Crease& c, std::vector<CreasePiece>& pieces) const;
  bool turnsAt(const FeatureLine& line, size_t k) const;
  int meetingVertex(const Vec3& x, const std::vector<int>& meeting);
  int endVertex(const Vec3& x, double reach);
  void addCreasePiece(const CreasePiece& p);
  static std::array<double, 3> key(const Vec3& p) { return { p.x, p.y, p.z }; }

  /// How far (grid steps) a curve found may run from a crease's point where its materials change:
  /// a V of two arms closer than a step is cut about a step over the angle between them short of
  /// its tip (8: arms down to about 7 degrees apart; below 60 the mesher is warned anyway).
  static constexpr double kMeetingReach = 8.0;

  const HierarchicalOracle& oracle_;
  const FeatureLineOptions& options_;
  FeatureCurveResampler& resampler_;
  FeatureLines& result_;
  double h_ = 0;
  double probe_ = 0;                                 // how far beside a crease its sides are probed
  std::map<std::array<double, 3>, int> creasePoint_; // crease ends -> point of result.segments
};
}
