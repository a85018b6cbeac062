// SPDX-License-Identifier: GPL-3.0-or-later
// Feature lines that arise where the oracle's inputs meet (the paper's future work):
// found with the oracle's own queries, decide(p) and the domains' exact crossings along segments.
#pragma once

#include "FeatureSegments.h"

#include <cstddef>
#include <functional>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace omesh
{
class HierarchicalOracle;

/// The default crease angle (degrees), the one source of it: FeatureLineOptions, selectFeatures, the
/// VTK filters' CreaseAngle, the plugin XML, the scene's features.feature_angle and the command line
/// read it from here. 60: the angle vtkFeatureEdges was given for a surface's sharp edges before.
constexpr double kDefaultCreaseAngle = 60.0;

/// Throws InputError unless 0 < angle <= 180 (180 = no creases: no faces' normals differ by more),
/// naming `what` (the option or property) in the message.
void checkCreaseAngle(double angle, const char* what);

/// How findFeatureLines searches and what it returns.
struct FeatureLineOptions
{
  /// Step of the search grid: curves shorter than about this, or closer to each other, can be
  /// missed. 0 = half of maxSegmentLength, else 1/64 of the oracle's bounding-box diagonal.
  double spacing = 0.0;
  /// Each curve is resampled (resampleFeatureLines) to chords of at most this length whose dropped
  /// points lie within `tolerance` of them; 0 = keep one point per grid face the curve crosses.
  double maxSegmentLength = 0.0;
  double tolerance = 0.0; ///< 0 = 0.05 x maxSegmentLength
  /// Per material: a curve takes the smallest of its materials' lengths listed here (else
  /// maxSegmentLength): the local edge size (also the grid step's and the junction collapse's scale).
  std::map<int, double> materialSegmentLength;
  /// Chords longer than the segment length, for a mesher that splits them to the edge size
  /// itself (rule T1.2, as it does given lines): per material (a curve takes the smallest of its
  /// materials' values; none listed: the segment length), and for the creases of single inputs,
  /// whose points are the input's own, `creaseChordLength` (infinity: as long as the tolerance
  /// allows; 0 = as the curves found). Never below the segment length. Chords cut to the edge size
  /// beforehand made every junction and corner a star vertex whose shortest segment is the edge size,
  /// trimmed at a third of it (T1.1), and kept the other inputs' crossings on straight creases as
  /// vertices: the mesh grew finer around both (docs/journal/2026-12-01-feature-line-studies.md).
  std::map<int, double> materialChordLength;
  double creaseChordLength = 0.0;
  /// Per material: a curve's chords keep within the smallest of its materials' tolerances (those
  /// listed here, `tolerance` for the others): a tenth of the facet distance of what it separates.
  std::map<int, double> materialTolerance;
  /// Curves meeting at a shared vertex, or one curve turning, at less than this angle (degrees)
  /// are reported: the paper's termination argument needs 60.
  double smallAngle = 60.0;
  /// Creases of single inputs (Domain::creases) where their faces' normals differ by more than
  /// this (degrees; 0 < angle <= 180, else findFeatureLines throws InputError): a surface's sharp
  /// edges, as vtkFeatureEdges' FeatureAngle (the scene's features.feature_angle sets both); a
  /// box's edges and a cylinder's rims (90) at any angle below 90. 180 = no creases at all.
  double creaseAngle = kDefaultCreaseAngle;
  /// The grid has at most this many points; a finer spacing is widened (with a warning).
  std::size_t maximumGridPoints = 4000000;
  /// Called with a fraction in [0, 1]; return false to stop (findFeatureLines then throws
  /// FeatureSearchAborted).
  std::function<bool(double)> progress;
};

/// Thrown when FeatureLineOptions::progress asked to stop.
struct FeatureSearchAborted : std::runtime_error
{
  FeatureSearchAborted()
    : std::runtime_error("feature line search aborted")
  {
  }
};

/// One curve: a polyline through FeatureLines::segments.points.
struct FeatureLine
{
  std::vector<int> points;    ///< point indices in order; a closed curve repeats its first point last
  std::vector<int> materials; ///< the materials meeting along it, ascending (kOutside = -1 included)
  /// true: three or more materials meet (a triple line: implant entering bone, label maps);
  /// false: two materials, the interface creased where two inputs' boundaries meet (a cut rim).
  bool triple = false;
  /// true: a crease of one input (Domain::creases: a box's edge, a cylinder's rim, a surface's
  /// sharp edge) where that input is seen; its vertices lie on the crease.
  bool crease = false;
  bool closed() const { return points.size() > 2 && points.front() == points.back(); }
};

/// A vertex where curves meet (or one turns) at a small angle.
struct SmallFeatureAngle
{
  int point = -1;
  double degrees = 0.0;
};

struct FeatureLines
{
  FeatureSegments segments;       ///< every curve's chords; a vertex shared by curves is one point
  std::vector<FeatureLine> lines; ///< the same, curve by curve
  std::vector<SmallFeatureAngle> smallAngles;
  std::vector<std::string> warnings; ///< small angles, a widened grid
  double spacing = 0.0;              ///< the grid step used
  std::size_t gridFacesCrossed = 0;  ///< crossing points located (before resampling)
};

/// The vertices of `f` where segments meet at less than `below` degrees, the first five named in
/// `warnings` and the rest counted.
std::vector<SmallFeatureAngle> findSmallFeatureAngles(const FeatureSegments& f, double below, std::vector<std::string>& warnings);

/// The curves where three or more regions meet: a region is a material together with the domain
/// that decides it (HierarchicalOracle::decide), so that a cut-away point and a point outside every
/// domain differ although both are outside. Kept are the curves where three or more materials meet
/// and those where a two-material interface passes from one input's boundary to another's (a
/// crease: a cut plane's rim on the bone); curves where only non-interface boundaries meet (inside
/// one material) are dropped.
///
/// Method: the regions are sampled on a grid; every grid face next to two or more regions is
/// walked along its edges with the domains' exact crossings, and holds a curve when a pair of
/// regions changes an odd number of times around it. The crossing point is then located in the face
/// by bisection with the same test (to 1e-10 of the bounding-box diagonal), so every point found
/// lies on the true curve. Crossings of one grid cube with the same regions are joined; curves that
/// end in one cube meet at one shared vertex there (least-squares meeting point of their tangents).
/// Each curve's chords are then put back on the curve: a vertex where a chord crosses a domain's
/// bend plane (Domain::bendPlanes: a label map's cell planes, where the curve turns), located in
/// that plane by the same bisection, and chords whose midpoint lies farther than the tolerance from
/// the curve split at the curve's point halfway.
/// Then the creases of single inputs (Domain::creases: a box's edges, a finite cylinder's rims, a
/// surface's sharp edges above options.creaseAngle), the pieces where the input decides the material
/// on its side of the crease and another material lies across: their ends where they pass into
/// another input are that input's exact crossing along the crease, and one vertex with the curve
/// found there (an entry curve), moved onto it or split at it.
/// Throws InputError for an empty or unbounded oracle (HierarchicalOracle::bounds).
FeatureLines findFeatureLines(const HierarchicalOracle& oracle, const FeatureLineOptions& options = {});
}
