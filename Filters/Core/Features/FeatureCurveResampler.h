// SPDX-License-Identifier: GPL-3.0-or-later
// The fourth phase of the feature-line search (findFeatureLines): the curves into the result. Each
// is resampled on its own to its materials' chord length and tolerance (resampleFeatureLines),
// then, for a curve found, its chords are put back on the curve: vertices where it crosses the
// domains' bend planes and where a chord's midpoint strays beyond the tolerance. Curves found
// share their end vertices (junctions); the crease search adds its pieces the same way.
#pragma once

#include "FeatureCurveGraph.h"
#include "FeatureCurveLocator.h"
#include "OracleFeatureLines.h"

#include <functional>
#include <map>
#include <vector>

namespace omesh::featurelines
{
class FeatureCurveResampler
{
public:
  /// Appends to `result` (its segments and lines); `locator` puts points on curves found.
  FeatureCurveResampler(const FeatureLineOptions& options, const FeatureCurveLocator& locator, FeatureLines& result);

  /// The curves found: each chain of `graph` (curves, after the junction phase) whose regions a
  /// crossing tells (`crossings`: GridCrossings::crossings); a vertex where chains end is one point.
  void addCurves(const FeatureCurveGraph& graph, const std::vector<Crossing>& crossings,
    const std::vector<std::vector<int>>& chains);

  /// Resamples the curve through `points` (closed: back to the first, which is not repeated)
  /// for its materials and adds it as `line`; an open curve's ends are the result's points
  /// endPoint(0) and endPoint(1), asked for when reached (first end, inner points, last end).
  /// `regions`: the signature of a curve found (none for a crease, whose points are the input's own).
  void addResampledCurve(FeatureLine line, std::vector<Vec3> points, bool closed,
    const std::function<int(int)>& endPoint, const Signature* regions = nullptr);

  /// Appends to `out` the curve's points between a and b (both on it, neither appended) where the
  /// chord's midpoint lies farther than `tolerance` from the curve, recursively (`depth` levels).
  void splitOnCurve(const Vec3& a, const Vec3& b, const Signature& regions, double tolerance, int depth, std::vector<Vec3>& out) const;

  /// The regions of result.lines[line] when it is a curve found, else null.
  const Signature* signatureOf(int line) const;

private:
  void addCurve(const FeatureCurveGraph& graph, const std::vector<Crossing>& crossings, const std::vector<int>& chain,
    std::map<int, int>& sharedPoint);
  void resampleCurve(FeatureSegments& piece, const std::vector<int>& materials, bool crease) const;
  std::vector<Vec3> onCurve(const std::vector<Vec3>& along, const Signature& regions, double tolerance) const;
  std::vector<Vec3> withBends(const std::vector<Vec3>& along, const Signature& regions, double tolerance) const;

  const FeatureLineOptions& options_;
  FeatureCurveLocator locator_;
  FeatureLines& result_;
  std::map<int, Signature> signature_; // curve found (index in result.lines) -> its regions
};
}
