// SPDX-License-Identifier: GPL-3.0-or-later
#include "FeatureCurveLengths.h"

#include <algorithm>
#include <cmath>

namespace omesh::featurelines
{
double lengthFor(const FeatureLineOptions& options, const std::vector<int>& materials)
{
  double length = options.maxSegmentLength;
  for (int material : materials)
    if (auto it = options.materialSegmentLength.find(material); it != options.materialSegmentLength.end())
      length = length > 0 ? std::min(length, it->second) : it->second;
  return length;
}

double chordLengthFor(const FeatureLineOptions& options, const std::vector<int>& materials, bool crease)
{
  const double length = lengthFor(options, materials);
  if (length <= 0)
    return length;
  if (crease && options.creaseChordLength > 0)
    return std::max(length, options.creaseChordLength);
  double chord = HUGE_VAL;
  for (int material : materials)
    if (auto it = options.materialChordLength.find(material); it != options.materialChordLength.end())
      chord = std::min(chord, it->second);
  return std::isfinite(chord) ? std::max(length, chord) : length;
}

double toleranceFor(const FeatureLineOptions& options, const std::vector<int>& materials, double length)
{
  const double global = options.tolerance > 0 ? options.tolerance : 0.05 * length;
  double tolerance = HUGE_VAL;
  for (int material : materials)
    if (material >= 0)
    {
      auto it = options.materialTolerance.find(material);
      tolerance = std::min(tolerance, it != options.materialTolerance.end() ? it->second : global);
    }
  return std::isfinite(tolerance) ? tolerance : global;
}
}
