// SPDX-License-Identifier: GPL-3.0-or-later
#include "FeatureLinePreparation.h"

#include "FeatureEdgeSizes.h"
#include "HierarchicalOracle.h"
#include "OracleMesher.h"

#include <algorithm>
#include <limits>
#include <sstream>

namespace omesh
{
std::optional<FeatureSegments> simplifyGivenFeatureLines(const FeatureSegments& given, const MaterialCriteria& criteria,
  const HierarchicalOracle& oracle, FeatureNetworkReport& report, std::vector<std::string>& warnings)
{
  if (given.empty())
    return std::nullopt;
  const MeshCriteria::Values g = criteria.globalValues();
  double distance = g.facetDistance;
  for (const auto& [m, unused] : criteria.perMaterial)
    if (const double d = criteria.of(m).facetDistance; d > 0 && (distance <= 0 || d < distance))
      distance = d;
  FeatureNetworkTolerances tolerances;
  tolerances.edgeLength =
    g.edgeSize > 0 ? g.edgeSize : g.facetSize > 0 ? g.facetSize : norm(oracle.bounds().size()) / 40.0;
  // a line with a finer edge size of its own (or of its materials) keeps its detail: h is the finest
  if (!given.edgeSizes.empty() || hasMaterialEdgeSizes(criteria))
    for (double e : resolveFeatureEdgeSizes(given, criteria, oracle))
      if (e > 0)
        tolerances.edgeLength = std::min(tolerances.edgeLength, e);
  tolerances.chordTolerance = distance > 0 ? 0.5 * distance : 0.05 * tolerances.edgeLength;
  tolerances.inDomain = [&oracle](const Vec3& p) { return oracle.material(p) != kOutside; };
  FeatureSegments resampled = given;
  report = simplifyFeatureNetwork(resampled, tolerances);
  // each chord keeps the own edge size of the given line nearest to it
  transferEdgeSizes(given, resampled, std::numeric_limits<double>::infinity());
  if (resampled.segments.size() != given.segments.size() || resampled.points.size() != given.points.size())
  {
    std::ostringstream o;
    o << "feature lines simplified: " << given.segments.size() << " segments became " << resampled.segments.size()
      << " (chords up to " << tolerances.edgeLength << "; points closer than " << tolerances.mergeDistance()
      << " merged, spurs shorter than " << tolerances.spurLength() << " dropped; the lines moved by at most "
      << std::max(report.givenToSimplified, report.simplifiedToGiven) << ")";
    warnings.push_back(o.str());
  }
  return resampled;
}

void addFeatureNetworkStatistics(
  const FeatureNetworkReport& report, std::size_t givenSegments, std::map<std::string, double>& st)
{
  st["feature_segments_before_resampling"] = static_cast<double>(givenSegments);
  st["feature_network.points_merged"] = static_cast<double>(report.pointsMerged);
  st["feature_network.points_snapped"] = static_cast<double>(report.pointsSnapped);
  st["feature_network.spurs_dropped"] = static_cast<double>(report.spursDropped);
  st["feature_network.pieces_dropped"] = static_cast<double>(report.piecesDropped);
  st["feature_network.segments_outside_dropped"] = static_cast<double>(report.segmentsOutside);
  st["feature_network.short_pieces_length"] = report.shortPiecesLength;
  st["feature_network.given_to_simplified"] = report.givenToSimplified;
  st["feature_network.simplified_to_given"] = report.simplifiedToGiven;
  st["feature_network.smallest_angle"] = report.smallestAngle;
  st["feature_network.shortest_segment"] = report.shortestSegment;
}

void PreparedFeatureLines::addStatistics(std::map<std::string, double>& statistics) const
{
  if (network)
    addFeatureNetworkStatistics(*network, givenSegments, statistics);
}

PreparedFeatureLines prepareFeatureLines(const HierarchicalOracle& oracle, const FeatureSegments& given,
  FeatureSource source, MesherOptions& options, const std::function<bool(double)>& progress)
{
  PreparedFeatureLines out;
  out.givenSegments = given.segments.size();
  std::optional<FeatureSegments> simplified;
  const bool usesGiven = source == FeatureSource::Given || source == FeatureSource::Both;
  if (options.resampleFeatureLines && usesGiven)
  {
    given.checkEdgeSizes(); // named on the lines as given, before the simplification moves them
    FeatureNetworkReport report;
    simplified = simplifyGivenFeatureLines(given, options.criteria, oracle, report, out.warnings);
    if (simplified)
      out.network = report;
  }
  out.selection = selectFeatures(oracle, simplified ? *simplified : given, source, options.criteria, progress);
  out.warnings.insert(out.warnings.end(), out.selection.warnings.begin(), out.selection.warnings.end());
  options.resampleFeatureLines = false;
  return out;
}
}
