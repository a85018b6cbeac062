// SPDX-License-Identifier: GPL-3.0-or-later
#include "OracleFeatureLines.h"

#include "FeatureCreaseSearch.h"
#include "FeatureCurveGraph.h"
#include "FeatureCurveLocator.h"
#include "FeatureCurveResampler.h"
#include "FeatureGridSearch.h"
#include "FeatureJunctions.h"
#include "HierarchicalOracle.h"
#include "InputError.h"

#include <algorithm>
#include <sstream>

namespace omesh
{
namespace
{
std::string describe(const Vec3& p)
{
  std::ostringstream o;
  o << "(" << p.x << ", " << p.y << ", " << p.z << ")";
  return o.str();
}
}

std::vector<SmallFeatureAngle> findSmallFeatureAngles(const FeatureSegments& f, double below, std::vector<std::string>& warnings)
{
  std::vector<SmallFeatureAngle> found;
  const auto& P = f.points;
  std::vector<std::vector<int>> neighbours(P.size());
  for (const auto& s : f.segments)
  {
    neighbours[s[0]].push_back(s[1]);
    neighbours[s[1]].push_back(s[0]);
  }
  for (size_t v = 0; v < P.size(); ++v)
  {
    double smallest = 180.0;
    for (size_t a = 0; a < neighbours[v].size(); ++a)
      for (size_t b = a + 1; b < neighbours[v].size(); ++b)
        smallest = std::min(smallest, angleAt(P[v], P[neighbours[v][a]], P[neighbours[v][b]]));
    if (smallest < below)
    {
      found.push_back({ static_cast<int>(v), smallest });
      if (found.size() > 5)
        continue; // the first five named, the rest counted below
      std::ostringstream o;
      o.precision(3);
      o << "feature lines meet at " << smallest << " degrees at " << describe(P[v]) << " (below " << below
        << ": refinement may not end there; the vertex budget bounds it)";
      warnings.push_back(o.str());
    }
  }
  if (found.size() > 5)
  {
    double smallest = 180.0;
    for (const auto& a : found)
      smallest = std::min(smallest, a.degrees);
    std::ostringstream o;
    o.precision(3);
    o << "feature lines meet below " << below << " degrees at " << found.size() - 5
      << " more vertices (smallest angle of all " << smallest << " degrees)";
    warnings.push_back(o.str());
  }
  return found;
}

void checkCreaseAngle(double angle, const char* what)
{
  if (angle > 0.0 && angle <= 180.0)
    return;
  std::ostringstream o;
  o << what << " " << angle << " is out of range (above 0 to 180 degrees; 180 = no creases)";
  throw InputError(o.str());
}

FeatureLines findFeatureLines(const HierarchicalOracle& oracle, const FeatureLineOptions& options)
{
  using namespace featurelines;
  checkCreaseAngle(options.creaseAngle, "feature lines: creaseAngle");
  FeatureLines result;
  FeatureGridSearch grid(oracle, options, result.warnings);
  const GridCrossings found = grid.search();
  result.spacing = found.spacing;
  result.gridFacesCrossed = found.gridFacesCrossed;
  FeatureCurveGraph graph(found);
  std::vector<std::vector<int>> chains = graph.curves();
  trimArms(graph, chains);
  collapseShortCurves(graph, chains, found.crossings, options);
  FeatureCurveResampler resampler(options, FeatureCurveLocator(oracle, found.precision), result);
  resampler.addCurves(graph, found.crossings, chains);
  FeatureCreaseSearch(oracle, options, found.spacing, found.diagonal, resampler, result).addCreases();
  // Small angles: between curves at a shared vertex, and where one curve turns sharply.
  result.smallAngles = findSmallFeatureAngles(result.segments, options.smallAngle, result.warnings);
  reportProgress(options, 1.0);
  return result;
}
}
