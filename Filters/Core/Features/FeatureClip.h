// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include "FeatureSegments.h"

#include <cstddef>
#include <map>
#include <vector>

namespace omesh
{
class HierarchicalOracle;

/// Owner of a feature segment for clipFeatureSegments: a user's own line (kept wherever some
/// material touches it) rather than the sharp edges of one input.
constexpr int kUserLine = -1;

/// What clipFeatureSegments changed, per owner (kUserLine or the index of the input, in the
/// oracle's priority order, whose sharp edges the segments are).
struct FeatureClipCounts
{
  struct PerOwner
  {
    std::size_t removed = 0; ///< segments removed whole
    std::size_t split = 0;   ///< segments cut where they leave the domain (some of it kept)
  };
  std::map<int, PerOwner> owners;
  std::size_t removed() const;
  std::size_t split() const;
  bool changed() const { return removed() + split() > 0; }
};

/// Clips given feature lines to where they can be features of the meshed domain, before they are
/// merged (mergeFeatureSegments) and selected: a piece no material touches (outside every domain,
/// or cut away by a higher-priority cut) can never be a mesh edge and is removed, instead of being
/// kept, warned about and counted as missing by the coverage and validity checks.
///
/// `owners` (empty: all kUserLine; else one per segment) tells the user's lines from the sharp
/// edges of an input (scene `features.from_surface`). A user's line is kept wherever some material
/// touches it, inside a material too (a line the user wants as mesh edges). An input's sharp edge
/// is kept only where that input itself decides the material beside it (HierarchicalOracle::decide):
/// where a higher-priority input covers the edge (a part sunk in another one, or the edge of a
/// part inside a material of higher priority), the edge is no crease of the combined domain, the
/// mesh has no reason to have it, and it is clipped like a piece outside (the other input's own
/// boundary gives the combined domain its edges there, which a search finds). An owner that is a
/// cut keeps its edges where some material touches them (its cut rim).
///
/// Each segment is split at the parameters where any domain's material may change along it
/// (Domain::crossings: exact for planes, spheres, boxes and cylinders up to rounding, exact
/// segment/triangle intersections for surfaces), and each piece between them tested at its
/// midpoint and around it (a ring of probes perpendicular to it, so that a thin wedge beside an
/// edge is seen); a change no domain lists (rounding) is found by bisection to 1e-12 of the
/// segment. A segment crossing the boundary keeps its own end points and gets one new point where
/// it leaves, appended after the existing points, so that mergeFeatureSegments makes it one with
/// any given point there within rounding (the given point wins, being listed first), and
/// selectFeatures moves a found curve's end there. Pieces shorter than rounding (1e-10 of the lines'
/// bounding-box diagonal) are not kept. Own edge sizes and sources go with the pieces. Points that
/// no segment uses any more are removed.
FeatureClipCounts clipFeatureSegments(
  FeatureSegments& features, const HierarchicalOracle& oracle, const std::vector<int>& owners = {});
}
