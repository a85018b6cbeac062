// SPDX-License-Identifier: GPL-3.0-or-later
// The third phase of the feature-line search (findFeatureLines): the curves where they meet at
// junctions. A junction vertex is placed within its cube from the curves' tangents, and curves
// that meet at small angles run close to each other: arms that would fold back at the junction are
// trimmed, and curves between two junctions too short for the mesh to show collapse to one vertex.
#pragma once

#include "FeatureCurveGraph.h"
#include "OracleFeatureLines.h"

#include <vector>

namespace omesh::featurelines
{
/// Where curves meet at a small angle the last crossing of an arm can lie beyond the junction, and
/// the arm would turn back there (a fold at 0 degrees). Such crossings are left out of `chains`:
/// the arm runs straight to the junction.
void trimArms(const FeatureCurveGraph& graph, std::vector<std::vector<int>>& chains);

/// Curves between two junctions shorter than their chord length (lengthFor: curves crossing or
/// touching at a small angle run within a grid step of each other for a while, and each cube along
/// that stretch made a junction) collapse to one vertex: the mesh could not show them, and their
/// ends would meet the other curves there at angles down to 0 degrees. The junctions of each
/// collapsed group become the smallest of them, moved to their mean; `crossings` tell the curves'
/// materials (GridCrossings::crossings).
void collapseShortCurves(FeatureCurveGraph& graph, std::vector<std::vector<int>>& chains,
  const std::vector<Crossing>& crossings, const FeatureLineOptions& options);
}
