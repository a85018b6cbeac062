// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include "FeatureSegments.h"
#include "MeshCriteria.h"
#include "MeshingDeadline.h"
#include "ShapeSummary.h"
#include "TetMesh.h"

#include <cstddef>
#include <functional>
#include <stdexcept>
#include <vector>
#include <string>

namespace omesh
{
class HierarchicalOracle;

/// How constrained segments are handled.
enum class FeatureStrategy
{
  Conforming,    ///< the paper: Delaunay refinement with rules T1-T3, segments kept as Delaunay edges
  None,          ///< stock CGAL Mesh_3 on the labelled oracle (Pons et al.): segments ignored
  ProtectingBalls ///< CGAL's Mesh_domain_with_polyline_features_3 (Dey et al.)
};

const char* toString(FeatureStrategy s);

/// Every default of the mesher, the one source of them: the VTK filter starts from a
/// default-constructed MesherOptions (its getters on a fresh filter show these), and the plugin
/// XML, the scene loader, the command line and pvpython read them from there (a test compares).
struct MesherOptions
{
  FeatureStrategy strategy = FeatureStrategy::Conforming;
  MaterialCriteria criteria;
  /// Tetrahedra of any material with a minimal dihedral angle below this (degrees) are refined like
  /// bad cells: removes the flat tetrahedra (four cocircular points) that radius-edge refinement
  /// leaves. Raising it bounds the angles before optimisation, at a price in tetrahedra; not covered
  /// by CGAL's termination guarantee (refinement also stops at the vertex budget). 0 = off.
  double sliverAngle = 1.0;
  /// Every sequential run but ProtectingBalls' (whose balls CGAL's cells must see as they are;
  /// parallel runs take circumcentres): tetrahedra below this angle (degrees; the larger of it and
  /// `sliverAngle`) are refined, and a cell's refinement point is picked in a small ball around its
  /// circumcentre so that the tetrahedra its insertion makes reach this angle and it encroaches no
  /// restricted facet (Li and Teng's picking region, SliverAvoidingPoint.h): a sliver split at its
  /// circumcentre makes new slivers, and this bound alone, with circumcentres, ran the generated
  /// bone/implant cases at radius-edge 1.1 into the vertex budget. 0 = off (circumcentres, CGAL's
  /// point). < 0 = automatic (effectivePickingSliverAngle): 12 degrees where every material's
  /// radius-edge bound is at least 1.3, 8.7 (the paper's angle) where every one is at least the
  /// paper's 1.1, else off. Measured on generated bone/implant cases: at radius-edge 1.1 all 25 end
  /// above 8.7 degrees before optimisation (71k-843k tetrahedra); at 1.3, 1.5 and 2 all 15 end
  /// above 12 with 1.00-1.06x the tetrahedra of 8.7 (and the optimisers then have little left to
  /// do). An earlier state of the code ran one of them (an implant face on a voxel
  /// boundary) into the vertex budget at 1.1: refinement at such bounds is not covered by a
  /// termination guarantee, and the vertex budget still stops it (with a warning).
  double pickingSliverAngle = -1.0;
  /// Simplify and resample the feature lines before meshing (simplifyFeatureNetwork in
  /// FeatureNetworkSimplification.h), at h = the edge size (else the facet size, else 1/40 of the
  /// domain's diagonal): points closer than h merged, segments at less than 30 degrees sharing a
  /// trunk, spurs and pieces shorter than h dropped, chords of at most h within half the smallest
  /// facet distance (else h / 20) of the dropped points, segments that leave the domain dropped. For
  /// feature lines made of many tiny noisy segments (sharp edges of scanned surfaces); the scene
  /// files turn it on for sharp edges found on a surface. Statistics feature_network.*.
  bool resampleFeatureLines = false;
  /// Tetrahedra with at least three vertices on interfaces or feature lines and a minimal dihedral angle
  /// below this (degrees) are refined like bad cells: the optimisers cannot fix them. 0 = off.
  /// Below radius-edge 1.2 only those with a circumradius of at least 1/8 of their material's cell
  /// size (their circumcentres make smaller interface slivers: at 1.1 that converged onto points).
  /// Not covered by CGAL's termination guarantee: refinement also stops at the vertex budget.
  double interfaceSliverAngle = 10.0;
  /// Tetrahedra with all four vertices on interfaces or feature lines are refined below this
  /// (degrees; at least interfaceSliverAngle): the quality step moves no vertex where interfaces
  /// meet nor flips an interface triangle, so such a tetrahedron on a cut rim or a crease stayed at
  /// 11-13 degrees. -1 = improvementMinAngle (whether the step runs or not: the same refinement
  /// either way), 0 = only the interface rule above.
  double enclosedSliverAngle = -1.0;
  bool perturb = true;
  bool exude = true;
  /// The optimisation policy: each optimiser works where its work pays, in steps, not
  /// seconds, so a seed gives the same mesh on any machine.
  /// The perturber raises a bound on the smallest dihedral angle one degree at a time (CGAL's, up to
  /// 12); at a bound it cannot reach, a vertex that none of its perturbations moves costs all of them.
  /// It gives up at a bound after this many such vertices plus 1% of its attempts at that bound
  /// (statistics optimisation.perturbation_gave_up, _last_bound); 0 = never (CGAL's behaviour).
  double perturbationFailuresPerBound = 4.0;
  /// The exuder pumps the cells whose smallest dihedral angle is below this (degrees), worst first;
  /// 0 = every cell (CGAL's default, whose cost only its time limit bounds).
  double exudationSliverBound = 15.0;
  /// Step budgets of the sliver optimisers, a backstop (which the defaults above rarely reach):
  /// perturbation attempts per mesh vertex, cells pumped per cell of the complex; 0 = no budget
  /// (for the exuder, which can cycle, 10 per cell).
  /// Reaching one ends the phase (statistics optimisation.*_cut_short). Deterministic.
  double perturbationStepsPerVertex = 2.0;
  double exudationStepsPerCell = 0.1;
  /// Seconds for each of perturb and exude: 0 = no limit (the default: a limit makes the mesh
  /// depend on the machine's speed), < 0 = stock CGAL's default (the refinement's running time).
  double optimisationTimeLimit = 0.0;
  /// The quality step after the optimisers (improveDihedralAngles in DihedralImprovement.h): flips
  /// inside one material and vertex moves that keep feature lines and interfaces where they are,
  /// raising the tetrahedra with a dihedral angle outside [improvementMinAngle,
  /// improvementMaxAngle] degrees (FE-grade: small angles spoil the conditioning, large ones the
  /// gradients). In rounds, not seconds (statistics improvement.*).
  bool improveAngles = true;
  double improvementMinAngle = 15.0;
  double improvementMaxAngle = 155.0;
  /// 1: 4-node tetrahedra; 2: 10-node tetrahedra whose mid-edge nodes on interfaces lie on the
  /// oracle's surfaces (makeQuadraticTets in QuadraticTets.h). meshOracle makes the linear mesh either
  /// way; the VTK filter adds the mid-edge nodes.
  int elementOrder = 1;
  unsigned seed = 0;                  ///< same input + same seed = identical mesh (with threads = 1)
  /// Threads of the refinement. 1: sequential, the same seed gives the same mesh bit for bit.
  /// N > 1 (0 = every core): CGAL's parallel Mesh_3 refinement (Parallel_tag, TBB), for
  /// Conforming with feature lines above a read-only level that keeps points out of the
  /// sub-segments' diametral balls, then a sequential round where it refused some; the mesh meets
  /// the same criteria and passes the same checks (validity, feature lines, quality bounds) but
  /// differs from run to run. The threads refine cells at their circumcentres, then one thread
  /// refines the slivers they left at picked points (pickingSliverAngle); the optimisers run on one
  /// thread.
  int threads = 1;
  std::size_t maximumNumberOfVertices = 2000000; ///< 0 = unlimited; reaching it ends refinement with a warning
  /// Wall-clock seconds for the whole run, every phase (feature conformation and protection,
  /// refinement, optimisation, validation): reaching it throws TimeLimitReached (a failure naming the
  /// phase, with the statistics so far), for inputs whose criteria no budget of vertices bounds
  /// (refinement steps that insert nothing, optimiser steps on huge vertex stars).
  /// 0 = automatic: kDefaultTimeLimit (10 minutes), whatever the budget; < 0 = none. See
  /// effectiveTimeLimit(). Criteria that could not be met within it are refused before meshing
  /// (checkMeshSize in MeshSizeEstimate.h).
  double timeLimit = 0.0;
  /// Called during the work with a fraction in [0, 1] and the phase name; return false to abort
  /// (the call then throws MeshingAborted). Called from the calling thread.
  std::function<bool(double, const char*)> progress;
  /// Where each tetrahedron's shape measures go (summariseShapes, ShapeSummary.h), in buffers the
  /// caller owns: called once the output's size is known, with its number of tetrahedra. Unset:
  /// only the summary statistics are made.
  std::function<TetShapeArrays(std::size_t tetrahedra)> shapeArrays;
};

/// The automatic picking sliver angle (MesherOptions::pickingSliverAngle < 0): the paper's
/// minimal angle where every material's radius-edge bound is at least the paper's 1.1 (or none),
/// 12 degrees where every one is at least 1.3. Measured on the generated bone/implant cases (15
/// each): at 1.3, 1.5 and 2, 12 degrees ends all before optimisation with 1.00-1.06x the
/// tetrahedra of 8.7; at 1.1, 12 (and 10) degrees ran one case into the vertex budget and tripled
/// the others.
constexpr double kPickingSliverAngle = 8.7;
constexpr double kPickingSliverRadiusEdge = 1.1;
constexpr double kPickingSliverAngleLoose = 12.0;
constexpr double kPickingSliverRadiusEdgeLoose = 1.3;

/// The picking sliver angle a run with `options` gets, in degrees (0 = off).
double effectivePickingSliverAngle(const MesherOptions& options);

/// The automatic time limit (MesherOptions::timeLimit 0), seconds: a person waits minutes, not
/// hours; a run that needs longer is asked for (the limit raised) and is then bounded by that.
constexpr double kDefaultTimeLimit = 600.0;

/// The time limit a run with `options` gets, in seconds (0 = none).
double effectiveTimeLimit(const MesherOptions& options);

/// Thrown when the progress callback asked to stop.
struct MeshingAborted : std::runtime_error
{
  MeshingAborted()
    : std::runtime_error("meshing aborted")
  {
  }
};

/// Thrown when CGAL fails inside the mesher (an internal error, not the input's fault).
struct MeshingFailed : std::runtime_error
{
  using std::runtime_error::runtime_error;
};

/// Tetrahedralizes the domain of `oracle`, preserving `features` (see FeatureStrategy) and
/// inserting `seedPoints` first (the paper's a-priori points). Throws InputError for bad input
/// (empty oracle, bad feature lines, bad criteria).
TetMesh meshOracle(const HierarchicalOracle& oracle, const FeatureSegments& features,
  const std::vector<Vec3>& seedPoints, const MesherOptions& options);
}
