// SPDX-License-Identifier: GPL-3.0-or-later
// The meshing run's first step on the feature lines: resampled to the mesh size when asked, a
// warning when dense lines are not.
#include "FeatureLineResampling.h"

#include "FeatureEdgeSizes.h"

#include <algorithm>
#include <sstream>

namespace omesh
{
namespace
{
/// The chord length of the resampling: the edge size, else the facet size, else 1/40 of the diagonal.
double resamplingLength(const MesherOptions& options, const BoundingBox& inner)
{
  const MeshCriteria::Values g = options.criteria.globalValues();
  return g.edgeSize > 0 ? g.edgeSize : g.facetSize > 0 ? g.facetSize : norm(inner.size()) / 40.0;
}
}

std::optional<std::string> denseFeatureLinesWarning(
  const FeatureSegments& given, const MesherOptions& options, const BoundingBox& inner)
{
  constexpr size_t kManySegments = 1000;
  constexpr double kShorter = 10.0;
  if (options.resampleFeatureLines || given.segments.size() < kManySegments)
    return std::nullopt;
  std::vector<double> lengths(given.segments.size());
  for (size_t s = 0; s < lengths.size(); ++s)
    lengths[s] = given.length(s);
  std::nth_element(lengths.begin(), lengths.begin() + lengths.size() / 2, lengths.end());
  const double median = lengths[lengths.size() / 2], h = resamplingLength(options, inner);
  if (!(median * kShorter < h))
    return std::nullopt;
  std::ostringstream o;
  o.precision(3);
  o << "feature lines: " << given.segments.size() << " segments of median length " << median << ", " << h / median
    << " times shorter than the mesh size " << h
    << ": each of their points stays a mesh vertex and the mesh grades down to them (slow, and small "
       "elements); resample them to chords of about that size (ResampleFeatureLines), or raise the feature angle "
       "that found them";
  return o.str();
}

std::optional<FeatureSegments> resampledFeatures(const FeatureSegments& given, const MesherOptions& options,
  const HierarchicalOracle& oracle, const BoundingBox& inner, std::vector<std::string>& warnings,
  FeatureNetworkReport& report)
{
  if (!options.resampleFeatureLines || given.empty())
    return std::nullopt;
  const double distance = options.criteria.finestFacetDistance();
  FeatureNetworkTolerances tolerances;
  tolerances.edgeLength = resamplingLength(options, inner);
  // a line with a finer edge size of its own (or of its materials) keeps its detail: h is the finest
  if (!given.edgeSizes.empty() || hasMaterialEdgeSizes(options.criteria))
    for (double e : resolveFeatureEdgeSizes(given, options.criteria, oracle))
      if (e > 0)
        tolerances.edgeLength = std::min(tolerances.edgeLength, e);
  tolerances.chordTolerance = distance > 0 ? 0.5 * distance : 0.05 * tolerances.edgeLength;
  // merges, snaps and shared trunks keep the lines as near the given ones as the chords do: CAD
  // edges (a small polygonal circle, a corner) keep their shape (Benchmarks/cad_defects item 6)
  tolerances.maxDeviation = tolerances.chordTolerance;
  tolerances.inDomain = [&oracle](const Vec3& p) { return oracle.material(p) != kOutside; };
  FeatureSegments resampled = given;
  // each chord keeps the own edge size of the given segment it came from (its source)
  report = simplifyFeatureNetwork(resampled, tolerances);
  if (resampled.segments.size() != given.segments.size() || resampled.points.size() != given.points.size())
  {
    // How far the lines kept lie from the given ones; apart from that, how far the given ones lie
    // from those kept, which also counts pieces dropped on purpose (outside the domain, spurs): not
    // movement.
    std::ostringstream o;
    o << "feature lines simplified: " << given.segments.size() << " segments became " << resampled.segments.size()
      << " (chords up to " << tolerances.edgeLength << "; points closer than " << tolerances.mergeDistance()
      << " merged, spurs shorter than " << tolerances.spurLength() << " dropped; the lines kept lie within "
      << report.simplifiedToGiven << " of the given ones";
    if (report.givenToSimplified > report.simplifiedToGiven)
      o << ", the given ones within " << report.givenToSimplified << " of those kept (" << report.segmentsOutside
        << " segment(s) outside the domain, " << report.spursDropped << " spur(s), " << report.piecesDropped
        << " short piece(s) dropped, " << report.unmeshableEnds << " unmeshable end(s) bypassed or dropped, "
        << report.pointsSnapped << " snap(s) and shared trunk(s))";
    o << ")";
    warnings.push_back(o.str());
  }
  return resampled;
}
}
