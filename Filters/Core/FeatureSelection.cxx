// SPDX-License-Identifier: GPL-3.0-or-later
#include "FeatureSelection.h"

#include "FeatureMerge.h"
#include "HierarchicalOracle.h"
#include "MeshCriteria.h"

#include <set>

namespace omesh
{
const char* toString(FeatureSource s)
{
  switch (s)
  {
    case FeatureSource::None:
      return "None";
    case FeatureSource::Given:
      return "Given";
    case FeatureSource::Automatic:
      return "Automatic";
    case FeatureSource::Both:
      return "Both";
  }
  return "?";
}

FeatureLineOptions featureLineOptions(const HierarchicalOracle& oracle, const MaterialCriteria& criteria)
{
  FeatureLineOptions o;
  auto lengthOf = [&](const MeshCriteria::Values& v) {
    return v.edgeSize > 0 ? v.edgeSize : v.facetSize > 0 ? v.facetSize : 0.0;
  };
  const MeshCriteria::Values g = criteria.globalValues();
  o.maxSegmentLength = lengthOf(g) > 0 ? lengthOf(g) : norm(oracle.bounds().size()) / 40.0;
  double distance = g.facetDistance;
  double finest = o.maxSegmentLength;
  for (const auto& [m, unused] : criteria.perMaterial)
  {
    const MeshCriteria::Values v = criteria.of(m);
    if (lengthOf(v) > 0)
    {
      o.materialSegmentLength[m] = lengthOf(v);
      finest = std::min(finest, lengthOf(v));
    }
    if (v.facetDistance > 0 && (distance <= 0 || v.facetDistance < distance))
      distance = v.facetDistance;
  }
  // a tenth of the facet distance (issue 13's aim for the curves' deviation), not the half that
  // resampling given lines uses: these chords are the mesh's edges on the curve
  o.tolerance = distance > 0 ? 0.1 * distance : 0.05 * finest;
  o.spacing = 0.5 * finest;
  return o;
}

FeatureSelection selectFeatures(const HierarchicalOracle& oracle, const FeatureSegments& given, FeatureSource source,
  const MaterialCriteria& criteria, const std::function<bool(double)>& progress)
{
  FeatureSelection out;
  if (source == FeatureSource::Given || source == FeatureSource::Both)
    out.segments = given;
  if (source != FeatureSource::Automatic && source != FeatureSource::Both)
    return out;
  FeatureLineOptions options = featureLineOptions(oracle, criteria);
  options.progress = progress;
  out.automatic = findFeatureLines(oracle, options);
  out.warnings = out.automatic.warnings;
  const int offset = static_cast<int>(out.segments.points.size());
  const std::size_t firstAutomatic = out.segments.segments.size();
  out.segments.points.insert(out.segments.points.end(), out.automatic.segments.points.begin(),
    out.automatic.segments.points.end());
  for (auto s : out.automatic.segments.segments)
    out.segments.segments.push_back({ s[0] + offset, s[1] + offset });
  if (firstAutomatic == 0 || out.automatic.segments.empty())
    return out;
  // Given lines win over automatic ones that cross them.
  std::set<std::size_t> drop;
  for (const auto& [s, t] : out.segments.crossingPairs())
  {
    const bool sAuto = s >= firstAutomatic, tAuto = t >= firstAutomatic;
    if (sAuto != tAuto)
      drop.insert(sAuto ? s : t);
  }
  if (drop.empty())
    return out;
  std::vector<std::array<int, 2>> kept;
  for (std::size_t s = 0; s < out.segments.segments.size(); ++s)
    if (!drop.count(s))
      kept.push_back(out.segments.segments[s]);
  out.segments.segments = std::move(kept);
  out.droppedAutomatic = drop.size();
  out.warnings.push_back("feature lines: " + std::to_string(drop.size()) +
    " segment(s) of the lines found where inputs meet cross given lines and were dropped (the given ones are kept)");
  mergeFeatureSegments(out.segments); // drops the points no segment uses any more
  return out;
}
}
