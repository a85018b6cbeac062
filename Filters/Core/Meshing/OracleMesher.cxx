// SPDX-License-Identifier: GPL-3.0-or-later
// The mesher: the translation unit that instantiates CGAL Mesh_3 on the sequential triangulation (it
// takes about a minute to compile; ParallelRefinement.cxx has the parallel one). Relies on Mesh_3
// internals of CGAL 5.5 (Mesher_3 stepping, criteria classes, Mesh_3::internal::init_c3t3*); CMake
// warns on other CGAL versions.
#include "OracleMesher.h"

#include "MeshingRun.h"
#include "SequentialTypes.h"

#include <CGAL/assertions_behaviour.h>

#include <algorithm>
#include <string>

namespace omesh
{
double effectivePickingSliverAngle(const MesherOptions& options)
{
  if (options.pickingSliverAngle >= 0)
    return options.pickingSliverAngle;
  // the tightest radius-edge bound of any material (0 = none: counted as the paper's)
  auto bound = [](const MeshCriteria::Values& v) {
    return v.cellRadiusEdgeRatio > 0 ? v.cellRadiusEdgeRatio : kPickingSliverRadiusEdge;
  };
  double tightest = bound(options.criteria.globalValues());
  for (const auto& entry : options.criteria.perMaterial)
    tightest = std::min(tightest, bound(options.criteria.of(entry.first)));
  if (tightest >= kPickingSliverRadiusEdgeLoose)
    return kPickingSliverAngleLoose;
  return tightest >= kPickingSliverRadiusEdge ? kPickingSliverAngle : 0.0;
}

double effectiveTimeLimit(const MesherOptions& options)
{
  if (options.timeLimit != 0)
    return options.timeLimit > 0 ? options.timeLimit : 0.0;
  return kDefaultTimeLimit;
}

const char* toString(FeatureStrategy s)
{
  switch (s)
  {
    case FeatureStrategy::Conforming:
      return "Conforming";
    case FeatureStrategy::None:
      return "None";
    case FeatureStrategy::ProtectingBalls:
      return "ProtectingBalls";
  }
  return "?";
}

namespace
{
using namespace omesh::cgal;
using namespace omesh::cgal::sequential;

/// CGAL reports a failed assertion by printing its text to stderr, then throwing. For the time of
/// one meshing call it only throws; meshOracle turns the exception into its own message.
class QuietCgalErrors
{
public:
  QuietCgalErrors()
    : error_(CGAL::set_error_handler(&quiet))
    , warning_(CGAL::set_warning_handler(&quiet))
  {
  }
  ~QuietCgalErrors()
  {
    CGAL::set_error_handler(error_);
    CGAL::set_warning_handler(warning_);
  }
  QuietCgalErrors(const QuietCgalErrors&) = delete;
  QuietCgalErrors& operator=(const QuietCgalErrors&) = delete;

private:
  static void quiet(const char*, const char*, const char*, int, const char*) {}
  CGAL::Failure_function error_, warning_;
};


TetMesh meshOracleUnguarded(const HierarchicalOracle& oracle, const FeatureSegments& givenFeatures,
  const std::vector<Vec3>& seedPoints, const MesherOptions& options)
{
  try
  {
    return MeshingRun(oracle, givenFeatures, options).run(seedPoints);
  }
  catch (const ParallelBudgetReached& stop)
  {
    // the sequential run's mesh, as a one-thread run gives it, in what is left of the time limit
    MesherOptions one = options;
    one.threads = 1;
    const double limit = effectiveTimeLimit(options);
    if (limit > 0)
      one.timeLimit = std::max(1e-3, limit - stop.seconds);
    TetMesh mesh = MeshingRun(oracle, givenFeatures, one).run(seedPoints);
    mesh.warnings.push_back("Threads = " + std::to_string(requestedThreads(options)) +
      ": the parallel refinement reached MaximumNumberOfVertices = " +
      std::to_string(options.maximumNumberOfVertices) + " (" + std::to_string(stop.vertices) +
      " vertices) and was refined again on one thread: a parallel run stopped early leaves its vertices in deep "
      "clusters (flat tetrahedra), the sequential run spreads them; raise the budget or loosen the criteria");
    mesh.statistics["parallel.budget_retry_seconds"] = stop.seconds;
    return mesh;
  }
}
}

TetMesh meshOracle(const HierarchicalOracle& oracle, const FeatureSegments& features,
  const std::vector<Vec3>& seedPoints, const MesherOptions& options)
{
  QuietCgalErrors quiet;
  try
  {
    return meshOracleUnguarded(oracle, features, seedPoints, options);
  }
  catch (const CGAL::Failure_exception& e)
  {
    std::string where = e.filename();
    where = where.substr(where.find_last_of('/') + 1) + ":" + std::to_string(e.line_number());
    std::string why;
    if (e.message().find("already inserted") != std::string::npos)
      why = ": a refinement point repeats an existing vertex";
    throw MeshingFailed("meshing failed inside CGAL Mesh_3 (" + where + ")" + why +
      "; please report it with the scene (the seed reproduces it)");
  }
}
}
