// SPDX-License-Identifier: GPL-3.0-or-later
// The stock-CGAL side of the peer benchmark (peer_benchmark.py): CGAL 5.5 Mesh_3 as its manual
// shows it, on the same inputs and criteria as PeerOracleMesh.
//   labels  -> Labeled_mesh_domain_3::create_labeled_image_mesh_domain over an Image_3
//   surface -> Polyhedral_mesh_domain_3 over a Surface_mesh
//   cad     -> Polyhedral_mesh_domain_with_features_3, the given feature segments as polylines
//              (protecting balls, edge_size)
// Refinement (make_mesh_3 without optimisers: initialisation + refinement), perturb_mesh_3 and
// exude_mesh_3 are timed separately. --opt default reproduces make_mesh_3's defaults: each
// optimiser limited to the refinement's time. Prints one JSON line (PeerCommon.h).
#include "PeerCommon.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Image_3.h>
#include <CGAL/Labeled_mesh_domain_3.h>
#include <CGAL/Mesh_complex_3_in_triangulation_3.h>
#include <CGAL/Mesh_criteria_3.h>
#include <CGAL/Mesh_triangulation_3.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polyhedral_mesh_domain_3.h>
#include <CGAL/Polyhedral_mesh_domain_with_features_3.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/exude_mesh_3.h>
#include <CGAL/make_mesh_3.h>
#include <CGAL/perturb_mesh_3.h>
#include <CGAL/tetrahedral_remeshing.h>

#include <unordered_map>

namespace
{
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = K::Point_3;
namespace params = CGAL::parameters;
namespace PMP = CGAL::Polygon_mesh_processing;

template <class PolygonMesh>
void toPolygonMesh(const omesh::TriangleSurface& s, PolygonMesh& out)
{
  std::vector<Point> points;
  for (const auto& p : s.points)
    points.emplace_back(p.x, p.y, p.z);
  std::vector<std::vector<std::size_t>> polygons;
  for (const auto& t : s.triangles)
    polygons.push_back({ std::size_t(t[0]), std::size_t(t[1]), std::size_t(t[2]) });
  PMP::orient_polygon_soup(points, polygons);
  PMP::polygon_soup_to_polygon_mesh(points, polygons, out);
}

template <class C3t3>
omesh::TetMesh toTetMesh(const C3t3& c3t3)
{
  using Vh = typename C3t3::Triangulation::Vertex_handle;
  omesh::TetMesh out;
  std::unordered_map<Vh, int> ids;
  auto id = [&](Vh v) {
    auto [it, inserted] = ids.emplace(v, static_cast<int>(out.points.size()));
    if (inserted)
    {
      const auto& p = v->point().point();
      out.points.push_back({ CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z()) });
    }
    return it->second;
  };
  out.tets.reserve(c3t3.number_of_cells_in_complex());
  for (auto c = c3t3.cells_in_complex_begin(); c != c3t3.cells_in_complex_end(); ++c)
  {
    out.tets.push_back({ id(c->vertex(0)), id(c->vertex(1)), id(c->vertex(2)), id(c->vertex(3)) });
    out.tetMaterial.push_back(static_cast<int>(c3t3.subdomain_index(c)));
  }
  return out;
}

template <class C3t3, class Domain, class Criteria>
int run(const peer::Args& a, const Domain& domain, const Criteria& criteria, double setupSeconds,
  const omesh::FeatureSegments& features)
{
  CGAL::get_default_random() = CGAL::Random(a.seed);
  const auto t0 = peer::Clock::now();
  const double cpu0 = peer::cpuSeconds();
  C3t3 c3t3 = CGAL::make_mesh_3<C3t3>(domain, criteria, params::no_perturb(), params::no_exude());
  const double refine = peer::since(t0);
  const double refineCpu = peer::cpuSeconds() - cpu0;
  double minRefined = 180.0;
  for (auto c = c3t3.cells_in_complex_begin(); c != c3t3.cells_in_complex_end(); ++c)
  {
    auto v = [&](int i) {
      const auto& p = c->vertex(i)->point().point();
      return omesh::Vec3{ CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z()) };
    };
    minRefined = std::min(minRefined, omesh::minDihedralAngle(v(0), v(1), v(2), v(3)));
  }
  const double optCpu0 = peer::cpuSeconds();
  double perturb = 0, exude = 0;
  if (a.opt != "none")
  {
    const double limit = a.opt == "default" || a.opt == "remesh" ? refine : a.limit; // make_mesh_3's default: the refinement's time
    auto t1 = peer::Clock::now();
    CGAL::perturb_mesh_3(c3t3, domain, params::time_limit = limit);
    perturb = peer::since(t1);
    t1 = peer::Clock::now();
    CGAL::exude_mesh_3(c3t3, params::time_limit = limit);
    exude = peer::since(t1);
  }
  double remesh = 0;
  if (a.opt == "remesh")
  {
    // CGAL's Tetrahedral_remeshing on the complex (interfaces and the complex's feature edges kept),
    // at the mean edge length of the optimised mesh (the same density), 3 iterations as its examples
    double sum = 0;
    std::size_t count = 0;
    for (auto c = c3t3.cells_in_complex_begin(); c != c3t3.cells_in_complex_end(); ++c)
      for (int i = 0; i < 4; ++i)
        for (int j = i + 1; j < 4; ++j)
        {
          const auto& p = c->vertex(i)->point().point();
          const auto& q = c->vertex(j)->point().point();
          sum += std::sqrt(CGAL::to_double(CGAL::squared_distance(p, q)));
          ++count;
        }
    const auto t1 = peer::Clock::now();
    CGAL::tetrahedral_isotropic_remeshing(c3t3, count ? sum / count : 1.0, params::number_of_iterations(3));
    remesh = peer::since(t1);
  }
  const double optimise = perturb + exude + remesh;
  const double optimiseCpu = peer::cpuSeconds() - optCpu0;
  const omesh::TetMesh mesh = toTetMesh(c3t3);
  const double call = peer::since(t0);
  const double cpu = peer::cpuSeconds() - cpu0;
  const double rss = peer::peakRssBytes();
  std::ostringstream extra;
  extra << ", \"remesh\": " << remesh << ", \"refine_cpu\": " << refineCpu << ", \"optimise_cpu\": " << optimiseCpu << ", \"min_refined\": " << minRefined;
  peer::report("CGAL", a, mesh, setupSeconds, refine, perturb, exude, optimise, call, rss, cpu, features, extra.str());
  return 0;
}
}

int main(int argc, char* argv[])
{
  try
  {
    const peer::Args a = peer::parseArgs(argc, argv);
    if (a.threads != 1)
      throw std::runtime_error("--threads: the stock CGAL peer meshes on one thread");
    auto criteriaFor = [&](auto tag) {
      using Criteria = decltype(tag);
      if (a.kind == "cad")
        return Criteria(params::edge_size = a.edgeSize, params::facet_angle = a.facetAngle,
          params::facet_size = a.facetSize, params::facet_distance = a.facetDistance,
          params::cell_radius_edge_ratio = a.radiusEdge, params::cell_size = a.cellSize);
      return Criteria(params::facet_angle = a.facetAngle, params::facet_size = a.facetSize,
        params::facet_distance = a.facetDistance, params::cell_radius_edge_ratio = a.radiusEdge,
        params::cell_size = a.cellSize);
    };
    const auto s0 = peer::Clock::now();
    if (a.kind == "labels")
    {
      using Domain = CGAL::Labeled_mesh_domain_3<K>;
      using Tr = CGAL::Mesh_triangulation_3<Domain, CGAL::Default, CGAL::Sequential_tag>::type;
      using C3t3 = CGAL::Mesh_complex_3_in_triangulation_3<Tr>;
      using Criteria = CGAL::Mesh_criteria_3<Tr>;
      const peer::LabelImage im = peer::readLabels(a.input);
      _image* raw = ::_createImage(im.dims[0], im.dims[1], im.dims[2], 1, im.spacing[0], im.spacing[1],
        im.spacing[2], 1, WK_FIXED, SGN_UNSIGNED);
      raw->tx = im.origin[0];
      raw->ty = im.origin[1];
      raw->tz = im.origin[2];
      std::copy(im.labels.begin(), im.labels.end(), static_cast<unsigned char*>(raw->data));
      CGAL::Image_3 image(raw);
      CGAL::Random rng(a.seed);
      Domain domain = Domain::create_labeled_image_mesh_domain(image, params::p_rng = &rng);
      return run<C3t3>(a, domain, criteriaFor(Criteria()), peer::since(s0), {});
    }
    const omesh::TriangleSurface surface = peer::readOff(a.input);
    if (a.kind == "surface")
    {
      using Mesh = CGAL::Surface_mesh<Point>;
      using Domain = CGAL::Polyhedral_mesh_domain_3<Mesh, K>;
      using Tr = CGAL::Mesh_triangulation_3<Domain, CGAL::Default, CGAL::Sequential_tag>::type;
      using C3t3 = CGAL::Mesh_complex_3_in_triangulation_3<Tr>;
      using Criteria = CGAL::Mesh_criteria_3<Tr>;
      Mesh mesh;
      toPolygonMesh(surface, mesh);
      CGAL::Random rng(a.seed);
      Domain domain(mesh, &rng);
      return run<C3t3>(a, domain, criteriaFor(Criteria()), peer::since(s0), {});
    }
    using Domain = CGAL::Polyhedral_mesh_domain_with_features_3<K>;
    using Tr = CGAL::Mesh_triangulation_3<Domain, CGAL::Default, CGAL::Sequential_tag>::type;
    using C3t3 = CGAL::Mesh_complex_3_in_triangulation_3<Tr, Domain::Corner_index, Domain::Curve_index>;
    using Criteria = CGAL::Mesh_criteria_3<Tr>;
    const omesh::FeatureSegments features = peer::readSegments(a.features);
    Domain::Polyhedron polyhedron;
    toPolygonMesh(surface, polyhedron);
    CGAL::Random rng(a.seed);
    Domain domain(polyhedron, &rng);
    std::vector<std::vector<Point>> polylines;
    for (const auto& s : features.segments)
    {
      const auto& p = features.points[s[0]];
      const auto& q = features.points[s[1]];
      polylines.push_back({ Point(p.x, p.y, p.z), Point(q.x, q.y, q.z) });
    }
    domain.add_features(polylines.begin(), polylines.end());
    return run<C3t3>(a, domain, criteriaFor(Criteria()), peer::since(s0), features);
  }
  catch (const std::exception& e)
  {
    std::fprintf(stderr, "PeerCgal: %s\n", e.what());
    return 2;
  }
}
