// SPDX-License-Identifier: GPL-3.0-or-later
// Oracle query throughput on the demo scene, side by side with CGAL Mesh_3's own domain oracles
// on the same input (Labeled_mesh_domain_3 over an Image_3 for the label map,
// Polyhedral_mesh_domain_3 for the surface). One thread, deterministic query points.
//   usage: OracleBenchmark <Data/demo folder> [queries] [smooth|trilinear|nearest]
// (the last: the tibia's interpolation, default the vtkLabelMapDomain default, Smooth)
#include "HierarchicalOracle.h"
#include "LabelMapDomain.h"
#include "OracleBuilder.h"
#include "SurfaceDomain.h"
#include "TriangleSurface.h"
#include "DemoScenePipeline.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Image_3.h>
#include <CGAL/Labeled_mesh_domain_3.h>
#include <CGAL/Polyhedral_mesh_domain_3.h>
#include <CGAL/Surface_mesh.h>

#include <vtkCylinder.h>
#include <vtkDataObject.h>
#include <vtkImageData.h>
#include <vtkMultiBlockDataSet.h>
#include <vtkNew.h>
#include <vtkPlane.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkSphereSource.h>
#include <vtkXMLImageDataReader.h>
#include <vtkXMLPolyDataReader.h>

#include <sys/resource.h>

#include <chrono>
#include <ctime>
#include <cstdio>
#include <functional>
#include <random>
#include <string>

namespace
{
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Mesh = CGAL::Surface_mesh<K::Point_3>;
using ImageDomain = CGAL::Labeled_mesh_domain_3<K>;
using PolyDomain = CGAL::Polyhedral_mesh_domain_3<Mesh, K>;

double PeakRssMiB()
{
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_maxrss / 1024.0;
}

double CpuSeconds()
{
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

/// Runs `query(i)` n times; returns queries per CPU second of this (one-threaded) process, i.e.
/// per core: wall time on a shared machine also counts the others' work.
double Rate(size_t n, const std::function<int(size_t)>& query, long& checksum)
{
  const double t0 = CpuSeconds();
  long sum = 0;
  for (size_t i = 0; i < n; ++i)
    sum += query(i);
  const double s = CpuSeconds() - t0;
  checksum += sum;
  return n / s;
}

std::vector<omesh::Vec3> UniformPoints(const omesh::BoundingBox& b, size_t n, unsigned seed)
{
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<omesh::Vec3> pts(n);
  for (auto& p : pts)
    p = { b.min.x + u(rng) * (b.max.x - b.min.x), b.min.y + u(rng) * (b.max.y - b.min.y), b.min.z + u(rng) * (b.max.z - b.min.z) };
  return pts;
}

/// Points within `noise` of the surface's vertices: the hard case (exact test, not the grid).
std::vector<omesh::Vec3> NearSurfacePoints(const omesh::TriangleSurface& s, size_t n, double noise, unsigned seed)
{
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<size_t> pick(0, s.triangles.size() - 1);
  std::uniform_real_distribution<double> u(0.0, 1.0), e(-noise, noise);
  std::vector<omesh::Vec3> pts(n);
  for (auto& p : pts)
  {
    const auto& t = s.triangles[pick(rng)];
    double a = u(rng), b = u(rng);
    if (a + b > 1)
    {
      a = 1 - a;
      b = 1 - b;
    }
    const omesh::Vec3 q = s.points[t[0]] + a * (s.points[t[1]] - s.points[t[0]]) + b * (s.points[t[2]] - s.points[t[0]]);
    p = q + omesh::Vec3{ e(rng), e(rng), e(rng) };
  }
  return pts;
}

K::Point_3 P(const omesh::Vec3& p) { return { p.x, p.y, p.z }; }

Mesh ToMesh(const omesh::TriangleSurface& s)
{
  Mesh m;
  std::vector<Mesh::Vertex_index> v;
  for (const auto& p : s.points)
    v.push_back(m.add_vertex(P(p)));
  for (const auto& t : s.triangles)
    m.add_face(v[t[0]], v[t[1]], v[t[2]]);
  return m;
}

void Row(const char* what, double ours, double peer, const char* peerName)
{
  if (peer > 0)
    std::printf("%-44s %12.3g %12.3g  %6.2fx  (%s)\n", what, ours, peer, ours / peer, peerName);
  else
    std::printf("%-44s %12.3g %12s  %7s\n", what, ours, "-", "-");
}
}

int main(int argc, char* argv[])
{
  if (argc < 2)
  {
    std::fprintf(stderr, "usage: %s <demo folder> [queries] [smooth|trilinear|nearest]\n", argv[0]);
    return 2;
  }
  const std::string dir = argv[1];
  const size_t n = argc > 2 ? std::stoul(argv[2]) : 2000000;
  long checksum = 0;

  // --- inputs through the VTK adapters, as a user builds them
  DemoScenePipeline demo(dir);
  vtkLabelMapDomain* labels = demo.tibia;
  if (argc > 3)
  {
    const std::string mode = argv[3];
    labels->SetInterpolation(mode == "nearest" ? vtkLabelMapDomain::NEAREST
        : mode == "trilinear"                  ? vtkLabelMapDomain::TRILINEAR
                                               : vtkLabelMapDomain::SMOOTH);
    labels->Update();
    demo.oracle->Update();
    std::printf("label map interpolation: %s\n", mode.c_str());
  }
  vtkXMLImageDataReader* imageReader = demo.imageReader;
  vtkMultiBlockDataSet* sceneOutput = demo.oracle->GetOutput();
  vtkNew<vtkSphereSource> bigSource; // 100,352 triangles
  bigSource->SetRadius(30);
  bigSource->SetCenter(0, 0, 45);
  bigSource->SetThetaResolution(224);
  bigSource->SetPhiResolution(226);
  vtkNew<vtkSurfaceDomain> big;
  big->SetInputConnection(bigSource->GetOutputPort());
  big->Update();

  const double rss0 = PeakRssMiB();
  auto t0 = std::chrono::steady_clock::now();
  auto labelOracle = OracleBuilder::BuildOracle(labels->GetOutput());
  auto t1 = std::chrono::steady_clock::now();
  const omesh::TriangleSurface bigSurface = OracleBuilder::ToTriangleSurface(big->GetOutput(), "sphere");
  auto bigOracle = OracleBuilder::BuildOracle(big->GetOutput());
  auto t2 = std::chrono::steady_clock::now();
  auto sceneOracle = OracleBuilder::BuildOracle(sceneOutput);
  auto t3 = std::chrono::steady_clock::now();
  const double rss1 = PeakRssMiB();
  auto secs = [](auto a, auto b) { return std::chrono::duration<double>(b - a).count(); };

  // --- the peers: CGAL Mesh_3's own oracles on the same data
  vtkImageData* img = imageReader->GetOutput();
  int dims[3];
  double spacing[3], origin[3];
  img->GetDimensions(dims);
  img->GetSpacing(spacing);
  img->GetOrigin(origin);
  _image* raw = ::_createImage(dims[0], dims[1], dims[2], 1, spacing[0], spacing[1], spacing[2], 1, WK_FIXED, SGN_UNSIGNED);
  raw->tx = origin[0];
  raw->ty = origin[1];
  raw->tz = origin[2];
  auto* voxels = static_cast<unsigned char*>(raw->data);
  vtkDataArray* labelArray = img->GetPointData()->GetScalars();
  for (vtkIdType i = 0; i < labelArray->GetNumberOfTuples(); ++i)
    voxels[i] = static_cast<unsigned char>(labelArray->GetTuple1(i));
  CGAL::Image_3 image(raw);
  auto t4 = std::chrono::steady_clock::now();
  ImageDomain imageDomain = ImageDomain::create_labeled_image_mesh_domain(image);
  auto t5 = std::chrono::steady_clock::now();
  Mesh bigMesh = ToMesh(bigSurface);
  PolyDomain polyDomain(bigMesh);
  auto t6 = std::chrono::steady_clock::now();

  std::printf("OracleBenchmark: %zu queries per row, one thread, per CPU second\n", n);
  std::printf("setup: label map %.3f s (CGAL Image_3 domain %.3f s), 100k-triangle surface %.3f s "
              "(CGAL Polyhedral domain %.3f s), whole scene %.3f s; peak RSS %.0f -> %.0f MiB\n\n",
    secs(t0, t1), secs(t4, t5), secs(t1, t2), secs(t5, t6), secs(t2, t3), rss0, rss1);
  std::printf("%-44s %12s %12s  %7s\n", "queries per second", "OracleMesh", "CGAL peer", "ratio");

  const auto labelPts = UniformPoints(labelOracle->bounds(), n, 1);
  auto imageInside = imageDomain.is_in_domain_object();
  Row("material(p), label map, uniform",
    Rate(n, [&](size_t i) { return labelOracle->material(labelPts[i]); }, checksum),
    Rate(n, [&](size_t i) { auto r = imageInside(P(labelPts[i])); return r ? int(*r) : -1; }, checksum),
    "Labeled_mesh_domain_3 Is_in_domain");

  const auto bigPts = UniformPoints(bigOracle->bounds(), n, 2);
  auto polyInside = polyDomain.is_in_domain_object();
  Row("material(p), 100k-triangle surface, uniform",
    Rate(n, [&](size_t i) { return bigOracle->material(bigPts[i]); }, checksum),
    Rate(n, [&](size_t i) { auto r = polyInside(P(bigPts[i])); return r ? int(*r) : -1; }, checksum),
    "Polyhedral_mesh_domain_3 Is_in_domain");
  const size_t nNear = n / 10;
  const auto nearPts = NearSurfacePoints(bigSurface, nNear, 0.05, 3);
  Row("material(p), 100k surface, within 0.05 mm",
    Rate(nNear, [&](size_t i) { return bigOracle->material(nearPts[i]); }, checksum),
    Rate(nNear, [&](size_t i) { auto r = polyInside(P(nearPts[i])); return r ? int(*r) : -1; }, checksum),
    "Polyhedral_mesh_domain_3 Is_in_domain");

  const auto scenePts = UniformPoints(sceneOracle->bounds(), n, 4);
  Row("material(p), whole demo hierarchy, uniform",
    Rate(n, [&](size_t i) { return sceneOracle->material(scenePts[i]); }, checksum), 0, "");

  // intersect(a, b) on short segments (2 mm, the scale of the mesher's dual edges)
  const size_t nSeg = n / 10;
  std::mt19937_64 rng(5);
  std::normal_distribution<double> g(0.0, 1.0);
  auto segmentEnds = [&](const std::vector<omesh::Vec3>& pts) {
    std::vector<omesh::Vec3> b(pts.size());
    for (size_t i = 0; i < pts.size(); ++i)
    {
      omesh::Vec3 d{ g(rng), g(rng), g(rng) };
      b[i] = pts[i] + (2.0 / omesh::norm(d)) * d;
    }
    return b;
  };
  const std::vector<omesh::Vec3> sceneA(scenePts.begin(), scenePts.begin() + nSeg);
  const auto sceneB = segmentEnds(sceneA);
  Row("intersect(a,b), whole demo hierarchy",
    Rate(nSeg, [&](size_t i) { return int(sceneOracle->intersect(sceneA[i], sceneB[i]).found); }, checksum), 0, "");
  const std::vector<omesh::Vec3> labelA(labelPts.begin(), labelPts.begin() + nSeg);
  const auto labelB = segmentEnds(labelA);
  auto imageIntersect = imageDomain.construct_intersection_object();
  Row("intersect(a,b), label map",
    Rate(nSeg, [&](size_t i) { return int(labelOracle->intersect(labelA[i], labelB[i]).found); }, checksum),
    Rate(nSeg, [&](size_t i) -> int {
      const auto x = imageIntersect(K::Segment_3(P(labelA[i]), P(labelB[i])));
      return std::get<2>(x) != 0;
    }, checksum),
    "Labeled_mesh_domain_3 bisection");
  const auto nearB = segmentEnds(nearPts);
  auto polyIntersect = polyDomain.construct_intersection_object();
  Row("intersect(a,b), 100k surface, near it",
    Rate(nNear, [&](size_t i) { return int(bigOracle->intersect(nearPts[i], nearB[i]).found); }, checksum),
    Rate(nNear, [&](size_t i) -> int {
      const auto x = polyIntersect(K::Segment_3(P(nearPts[i]), P(nearB[i])));
      return std::get<2>(x) != 0;
    }, checksum),
    "Polyhedral_mesh_domain_3 AABB");
  std::printf("\n(checksum %ld)\n", checksum);
  return 0;
}
