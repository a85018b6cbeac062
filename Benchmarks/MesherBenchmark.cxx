// SPDX-License-Identifier: GPL-3.0-or-later
// The three feature strategies side by side on the demo bone/implant scene, same oracle, same
// criteria: tetrahedra, vertices, wall time, peak memory (each run in its own process), dihedral
// angles, feature coverage and the Hausdorff distance of the implant's mesh boundary to the implant.
//   usage: MesherBenchmark <Data/demo folder> [radius-edge bound (1.1)] [vertex budget (300000)]
#include "FeatureSegments.h"
#include "HierarchicalOracle.h"
#include "MeshQuality.h"
#include "OracleBuilder.h"
#include "MeshingPipeline.h"
#include "OracleMesher.h"
#include "TriangleDistance.h"
#include "TriangleSurface.h"
#include "DemoScenePipeline.h"

#include <vtkFeatureEdges.h>
#include <vtkPolyData.h>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace
{
struct Result
{
  double tets = 0, vertices = 0, seconds = 0, minAngle = 0, meanAngle = 0, coverage = 0, hausdorff = 0;
  int budgetHit = 0;
  int stalled = 0;
};

Result Run(const omesh::HierarchicalOracle& oracle, const omesh::FeatureSegments& features,
  const omesh::TriangleSurface& implant, const omesh::MesherOptions& options)
{
  Result r;
  const auto t0 = std::chrono::steady_clock::now();
  omesh::PipelineInput input;
  input.lines = features;
  omesh::PipelineOptions pipeline;
  pipeline.mesher = options;
  pipeline.features = omesh::FeatureSource::Given;
  const omesh::TetMesh m = omesh::runMeshingPipeline(oracle, std::move(input), std::move(pipeline)).mesh;
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  r.tets = static_cast<double>(m.tets.size());
  r.vertices = static_cast<double>(m.points.size());
  r.minAngle = m.statistics.at("min_dihedral_angle");
  r.meanAngle = m.statistics.at("mean_min_dihedral_angle");
  r.coverage = m.statistics.at("feature_coverage");
  for (const auto& w : m.warnings)
  {
    r.budgetHit |= w.find("refinement stopped at MaximumNumberOfVertices") != std::string::npos;
    r.stalled |= w.find("refinement stalled") != std::string::npos;
  }
  omesh::TriangleSurface boundary; // the implant's side of the interfaces
  boundary.points = m.points;
  for (size_t f = 0; f < m.interfaceTriangles.size(); ++f)
    if ((m.interfaceMaterials[f][0] == 3) != (m.interfaceMaterials[f][1] == 3))
      boundary.triangles.push_back(m.interfaceTriangles[f]);
  r.hausdorff = boundary.triangles.empty() ? -1 : omesh::TriangleDistance::hausdorff(boundary, implant);
  return r;
}
}

int main(int argc, char* argv[])
{
  if (argc < 2)
  {
    std::fprintf(stderr, "usage: %s <demo folder> [radius-edge bound] [vertex budget] [edge size]\n", argv[0]);
    return 2;
  }
  const std::string dir = argv[1];
  const double ratio = argc > 2 ? std::atof(argv[2]) : 1.1;
  const size_t budget = argc > 3 ? std::strtoul(argv[3], nullptr, 10) : 300000;
  const double edgeSize = argc > 4 ? std::atof(argv[4]) : 1.0;

  DemoScenePipeline demo(dir);
  vtkNew<vtkFeatureEdges> edges; // the implant's sharp edges
  edges->SetInputConnection(demo.implantReader->GetOutputPort());
  edges->BoundaryEdgesOff();
  edges->NonManifoldEdgesOff();
  edges->ManifoldEdgesOff();
  edges->FeatureEdgesOn();
  edges->SetFeatureAngle(60);
  edges->Update();

  const auto oracle = OracleBuilder::BuildOracle(demo.oracle->GetOutput());
  const omesh::FeatureSegments features = OracleBuilder::ToFeatureSegments(edges->GetOutput());
  const omesh::TriangleSurface implantSurface = OracleBuilder::ToTriangleSurface(demo.implantReader->GetOutput(), "implant");

  // The demo scene's criteria (Data/demo/scene.json, "mesh"): the paper's (section 4) in the
  // scene's millimetres — circumradius 1 (implant, screw) and 3 (bone), facet distance 0.1 and 2 —
  // with a finer cortical shell (1.5, facet distance 0.5) and cancellous interface (1).
  omesh::MesherOptions base;
  base.criteria.global.cellRadiusEdgeRatio = ratio;
  base.criteria.global.facetAngle = 25.0;
  base.criteria.global.cellSize = 3.0;
  base.criteria.global.facetSize = 3.0;
  base.criteria.global.facetDistance = 2.0;
  base.criteria.global.edgeSize = edgeSize;
  auto perMaterial = [&](int m, double cell, double facet, double distance) {
    omesh::MeshCriteria c = omesh::MeshCriteria::inheritAll();
    c.cellSize = cell;
    c.facetSize = facet;
    c.facetDistance = distance;
    base.criteria.perMaterial[m] = c;
  };
  perMaterial(1, 1.5, 1.5, 0.5);
  perMaterial(2, 3.0, 3.0, 1.0);
  perMaterial(3, 1.0, 1.0, 0.1);
  perMaterial(4, 1.0, 1.0, 0.1);
  base.maximumNumberOfVertices = budget;
  base.seed = 1;

  std::printf("MesherBenchmark: demo scene, %zu feature segments, radius-edge %.2f, edge size %.2f, budget %zu vertices\n",
    features.segments.size(), ratio, edgeSize, budget);
  std::printf("%-16s %10s %9s %8s %9s %8s %8s %9s %10s %s\n", "strategy", "tets", "vertices", "time s",
    "peak MiB", "min dih", "mean", "coverage", "Hausdorff", "");
  Result none{};
  for (omesh::FeatureStrategy s : { omesh::FeatureStrategy::None, omesh::FeatureStrategy::ProtectingBalls,
         omesh::FeatureStrategy::Conforming })
  {
    // Each strategy in its own process: its own peak memory, and a crash cannot hide the others.
    std::fflush(stdout); // or the children print the parent's buffer again
    int fd[2];
    if (pipe(fd) != 0)
      return 1;
    const pid_t pid = fork();
    if (pid == 0)
    {
      close(fd[0]);
      omesh::MesherOptions o = base;
      o.strategy = s;
      const Result r = Run(*oracle, features, implantSurface, o);
      if (write(fd[1], &r, sizeof r) != sizeof r)
        _exit(1);
      _exit(0);
    }
    close(fd[1]);
    Result r{};
    const bool got = read(fd[0], &r, sizeof r) == sizeof r;
    close(fd[0]);
    int status = 0;
    rusage ru{};
    wait4(pid, &status, 0, &ru);
    if (!got)
    {
      std::printf("%-16s failed (status %d)\n", omesh::toString(s), status);
      continue;
    }
    if (s == omesh::FeatureStrategy::None)
      none = r;
    std::printf("%-16s %10.0f %9.0f %8.2f %9.0f %8.2f %8.2f %8.1f%% %10.3f %s\n", omesh::toString(s), r.tets,
      r.vertices, r.seconds, ru.ru_maxrss / 1024.0, r.minAngle, r.meanAngle, 100 * r.coverage, r.hausdorff,
      r.budgetHit ? "(vertex budget hit)" : r.stalled ? "(refinement stalled)" : "");
    std::fflush(stdout);
    if (s != omesh::FeatureStrategy::None && none.tets > 0)
      std::printf("%-16s %9.2fx %32s  time per tet %.2fx of None\n", "  vs None", r.tets / none.tets, "",
        (r.seconds / r.tets) / (none.seconds / none.tets));
  }
  return 0;
}
