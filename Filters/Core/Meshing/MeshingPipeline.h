// SPDX-License-Identifier: GPL-3.0-or-later
// The whole meshing pipeline behind every door: feature lines clipped to the meshed domain and
// merged, the lines to keep selected (given, found where the inputs meet, or both), the size
// checked, the mesh made (refinement, optimisers, quality step, checks), quadratic elements, and
// every warning about the inputs. The VTK filter converts its inputs, calls runMeshingPipeline and
// converts the result; C++ callers (the peers, the benchmarks) call it the same way.
#pragma once

#include "FeatureSegments.h"
#include "FeatureSelection.h"
#include "OracleMesher.h"
#include "QuadraticTets.h"
#include "TetMesh.h"

#include <string>
#include <vector>

namespace omesh
{
class HierarchicalOracle;

/// What to mesh, beside the oracle.
struct PipelineInput
{
  /// The given feature lines, and each segment's owner (FeatureClip.h: kUserLine, or the index of
  /// the input whose sharp edges it is; empty: all the user's).
  FeatureSegments lines;
  std::vector<int> owners;
  std::vector<Vec3> seedPoints;
  /// The caller's own warnings about the inputs (e.g. criteria for materials no input has),
  /// listed with the pipeline's after the placement warnings.
  std::vector<std::string> inputWarnings;
};

struct PipelineOptions
{
  MesherOptions mesher; ///< its criteria as merged by the caller (mergeCriteria); its progress, time limit
  FeatureSource features = kDefaultFeatureSource;
  double creaseAngle = kDefaultCreaseAngle;
};

struct PipelineResult
{
  /// The mesh; its warnings are every warning of the run: the pipeline's (clipping, merging,
  /// hidden domains, selection), then those about the inputs, then the mesher's.
  TetMesh mesh;
  QuadraticTetMesh quadratic;  ///< with mesher.elementOrder 2
  FeatureSelection selection;  ///< how the feature lines were chosen (each segment's origin)
  /// The warnings about the inputs (repairs, placement, units, vanished materials): a strict run
  /// fails on these.
  std::vector<std::string> inputWarnings;
};

/// Runs the pipeline. Progress: the line search (when lines are searched) takes the first tenth,
/// the mesher the rest. Throws InputError (bad input, criteria beyond the budget or the memory, an
/// empty mesh, with what removed everything), FeatureSearchAborted, MeshingAborted and
/// TimeLimitReached as the phases do.
PipelineResult runMeshingPipeline(const HierarchicalOracle& oracle, PipelineInput input, PipelineOptions options);
}
