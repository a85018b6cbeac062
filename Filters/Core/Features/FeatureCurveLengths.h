// SPDX-License-Identifier: GPL-3.0-or-later
// The lengths a feature curve between given materials is cut to and the tolerance its chords keep,
// from FeatureLineOptions' global and per-material values: the one place the phases of the
// feature-line search (collapsing short curves, resampling, joining crease ends) read them from.
#pragma once

#include "OracleFeatureLines.h"

#include <vector>

namespace omesh::featurelines
{
/// The chord length of a curve between these materials: the smallest listed, else the global one.
double lengthFor(const FeatureLineOptions& options, const std::vector<int>& materials);

/// The longest chord of a curve between these materials (a crease: `crease`), see
/// FeatureLineOptions::materialChordLength; never below lengthFor.
double chordLengthFor(const FeatureLineOptions& options, const std::vector<int>& materials, bool crease);

/// The chord tolerance of a curve between these materials: the smallest of their own
/// (options.materialTolerance), the global one for materials without.
double toleranceFor(const FeatureLineOptions& options, const std::vector<int>& materials, double length);
}
