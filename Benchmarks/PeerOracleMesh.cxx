// SPDX-License-Identifier: GPL-3.0-or-later
// The OracleMesh side of the peer benchmark (peer_benchmark.py): the core API (no VTK, no Python),
// the same kind of process as PeerCgal, on the same inputs and criteria.
//   labels  -> LabelMapDomain (Trilinear, as CGAL's labelled image domain; --interpolation)
//   surface -> SurfaceDomain
//   cad     -> SurfaceDomain + the given feature segments (Conforming)
// Strategy Conforming (the default), the mesher's default sliver rules. --opt default = the
// mesher's defaults (its optimisation policy, no time limit); none = refinement only; limit:T = stock
// CGAL's policy: perturb and exude each limited to T seconds, nothing else (no step budgets, no
// giving up at a bound, the exuder on every cell); previous = the defaults before issue 12's
// optimisation policy (step budgets only). Prints one JSON line (PeerCommon.h).
#include "PeerCommon.h"

#include "HierarchicalOracle.h"
#include "LabelMapDomain.h"
#include "MeshingPipeline.h"
#include "OracleMesher.h"
#include "SurfaceDomain.h"
#include "WorkerThreads.h"

#include <memory>

int main(int argc, char* argv[])
{
  try
  {
    const peer::Args a = peer::parseArgs(argc, argv);
    const auto s0 = peer::Clock::now();
    omesh::HierarchicalOracle oracle;
    omesh::FeatureSegments features;
    if (a.kind == "labels")
    {
      const peer::LabelImage im = peer::readLabels(a.input);
      std::vector<int> labels(im.labels.begin(), im.labels.end());
      const auto toVoxel = omesh::LabelMapDomain::pointCenteredWorldToVoxel(
        { im.origin[0], im.origin[1], im.origin[2] }, { im.spacing[0], im.spacing[1], im.spacing[2] },
        { 1, 0, 0, 0, 1, 0, 0, 0, 1 });
      oracle.add(std::make_shared<omesh::LabelMapDomain>(
        std::array<int, 3>{ im.dims[0], im.dims[1], im.dims[2] }, labels, toVoxel, 0, "labels",
        a.interpolation == "smooth"  ? omesh::LabelInterpolation::Smooth
          : a.interpolation == "nearest" ? omesh::LabelInterpolation::Nearest
                                         : omesh::LabelInterpolation::Trilinear));
    }
    else
    {
      oracle.add(std::make_shared<omesh::SurfaceDomain>(peer::readOff(a.input), 1, "surface"));
      if (a.kind == "cad")
        features = peer::readSegments(a.features);
    }
    const double setup = peer::since(s0);

    omesh::MesherOptions o;
    o.strategy = omesh::FeatureStrategy::Conforming;
    auto& c = o.criteria.global;
    c.facetAngle = a.facetAngle;
    c.facetSize = a.facetSize;
    c.facetDistance = a.facetDistance;
    c.cellSize = a.cellSize;
    c.cellRadiusEdgeRatio = a.radiusEdge;
    c.edgeSize = a.kind == "cad" ? a.edgeSize : 0.0;
    o.seed = a.seed;
    o.threads = a.threads;
    o.pickingSliverAngle = a.sliverAngle;
    o.improveAngles = a.improve;
    if (a.opt == "none")
      o.perturb = o.exude = false;
    else if (a.opt == "previous") // the defaults before issue 12's optimisation policy: step budgets only
      o.perturbationFailuresPerBound = o.exudationSliverBound = 0;
    else if (a.opt == "limit")
    {
      o.optimisationTimeLimit = a.limit;
      o.perturbationStepsPerVertex = 0;
      o.exudationStepsPerCell = 0;
      o.perturbationFailuresPerBound = 0; // CGAL's optimiser policy: only the time limits
      o.exudationSliverBound = 0;
    }
    const auto t0 = peer::Clock::now();
    const double cpu0 = peer::cpuSeconds();
    omesh::PipelineInput input;
    input.lines = features;
    omesh::PipelineOptions options;
    options.mesher = o;
    options.features = omesh::FeatureSource::Given;
    // on the threads asked, as the VTK filter runs it: outside runOnThreads the passes in chunks
    // (output, validity, the optimisers' scans) would take every core on a one-thread run
    omesh::TetMesh mesh;
    omesh::runOnThreads(a.threads, [&] { mesh = omesh::runMeshingPipeline(oracle, std::move(input), std::move(options)).mesh; });
    const double call = peer::since(t0);
    const double cpu = peer::cpuSeconds() - cpu0;
    const double rss = peer::peakRssBytes();
    const auto& st = mesh.statistics;
    auto stat = [&](const char* k) {
      auto it = st.find(k);
      return it == st.end() ? 0.0 : it->second;
    };
    std::ostringstream extra;
    extra << ", \"perturb_cut_short\": " << stat("optimisation.perturbation_cut_short")
          << ", \"exude_cut_short\": " << stat("optimisation.exudation_cut_short")
          << ", \"after_mesh\": " << (call - stat("time.initialisation") - stat("time.refinement") - stat("time.optimisation"))
          << ", \"warnings\": " << mesh.warnings.size()
          << ", \"refine_cpu\": " << stat("cpu.refinement") << ", \"optimise_cpu\": " << stat("cpu.optimisation")
          << ", \"refine_critical_cpu\": " << stat("cpu.refinement_critical_path")
          << ", \"min_refined\": " << stat("optimisation.min_dihedral_before")
          << ", \"improve\": " << stat("time.improvement")
          << ", \"output\": " << stat("time.output") << ", \"validity\": " << stat("time.validity")
          << ", \"statistics\": " << stat("time.statistics")
          << ", \"outside_held\": " << stat("improvement.outside_held");
    // Conforming on several threads: vertices after and seconds of each phase (sequential segments,
    // parallel, sequential tail)
    for (const auto& [key, value] : st)
      if (key.rfind("parallel_conforming.", 0) == 0)
        extra << ", \"" << key.substr(20) << "\": " << value;
    peer::report("OracleMesh", a, mesh, setup, stat("time.initialisation") + stat("time.refinement"),
      stat("time.perturbation"), stat("time.exudation"), stat("time.optimisation"), call, rss, cpu, features, extra.str());
    return 0;
  }
  catch (const std::exception& e)
  {
    std::fprintf(stderr, "PeerOracleMesh: %s\n", e.what());
    return 2;
  }
}
