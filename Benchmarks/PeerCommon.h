// SPDX-License-Identifier: GPL-3.0-or-later
// Shared by the two sides of the peer benchmark (PeerCgal.cxx: stock CGAL Mesh_3;
// PeerOracleMesh.cxx: OracleMesh's core): the input files, the command line, and the figures
// computed the same way for both from the output mesh. Core types only (no CGAL, no VTK).
//
// Input files (written by peer_benchmark.py):
//   labels: one text line "OMLABELS nx ny nz sx sy sz ox oy oz" then nx*ny*nz uint8 labels,
//           x fastest; point-centred (voxel (i,j,k) centred at o + (i sx, j sy, k sz)); 0 = background
//   surface: ASCII OFF of a closed triangle surface
//   features: one segment per line "2 x y z x y z" (CGAL's polyline text format)
#pragma once

#include "FeatureSegments.h"
#include "MeshQuality.h"
#include "MeshValidity.h"
#include "TetMesh.h"
#include "TriangleSurface.h"

#include <sys/resource.h>

#include <chrono>
#include <ctime>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <array>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace peer
{
struct LabelImage
{
  int dims[3] = { 0, 0, 0 };
  double spacing[3] = { 1, 1, 1 }, origin[3] = { 0, 0, 0 };
  std::vector<uint8_t> labels;
};

inline LabelImage readLabels(const std::string& path)
{
  std::ifstream in(path, std::ios::binary);
  std::string magic;
  LabelImage im;
  in >> magic >> im.dims[0] >> im.dims[1] >> im.dims[2] >> im.spacing[0] >> im.spacing[1] >> im.spacing[2] >>
    im.origin[0] >> im.origin[1] >> im.origin[2];
  if (!in || magic != "OMLABELS")
    throw std::runtime_error(path + ": not an OMLABELS file");
  in.get(); // the newline
  im.labels.resize(static_cast<size_t>(im.dims[0]) * im.dims[1] * im.dims[2]);
  in.read(reinterpret_cast<char*>(im.labels.data()), static_cast<std::streamsize>(im.labels.size()));
  if (!in)
    throw std::runtime_error(path + ": truncated");
  return im;
}

inline omesh::TriangleSurface readOff(const std::string& path)
{
  std::ifstream in(path);
  std::string magic;
  size_t nv = 0, nf = 0, ne = 0;
  in >> magic >> nv >> nf >> ne;
  if (!in || magic != "OFF")
    throw std::runtime_error(path + ": not an OFF file");
  omesh::TriangleSurface s;
  s.points.resize(nv);
  for (auto& p : s.points)
    in >> p.x >> p.y >> p.z;
  s.triangles.resize(nf);
  for (auto& t : s.triangles)
  {
    int k = 0;
    in >> k >> t[0] >> t[1] >> t[2];
    if (k != 3)
      throw std::runtime_error(path + ": only triangles");
  }
  if (!in)
    throw std::runtime_error(path + ": truncated");
  return s;
}

inline omesh::FeatureSegments readSegments(const std::string& path)
{
  std::ifstream in(path);
  omesh::FeatureSegments f;
  std::map<std::array<double, 3>, int> ids; // shared ends become one point (a polyline network)
  auto id = [&](const omesh::Vec3& p) {
    auto [it, inserted] = ids.emplace(std::array<double, 3>{ p.x, p.y, p.z }, static_cast<int>(f.points.size()));
    if (inserted)
      f.points.push_back(p);
    return it->second;
  };
  int k = 0;
  while (in >> k)
  {
    if (k != 2)
      throw std::runtime_error(path + ": one two-point segment per line");
    omesh::Vec3 a, b;
    in >> a.x >> a.y >> a.z >> b.x >> b.y >> b.z;
    f.segments.push_back({ id(a), id(b) });
  }
  return f;
}

/// The command line both programs take:
///   <labels|surface|cad> <input> [features] [--cell-size x] [--facet-size x] [--facet-distance x]
///   [--facet-angle x] [--radius-edge x] [--edge-size x] [--opt default|none|limit:T] [--seed n]
///   [--threads n] [--sliver-angle degrees] [--interpolation nearest|trilinear|smooth] [--write path]
///   [--improve on|off]
/// --opt: default = the tool's own default optimisation; none = refinement only; limit:T = perturb
/// and exude each limited to T seconds and nothing else (no step budgets); previous (OracleMesh
/// only) = its defaults before issue 12's optimisation policy. --threads (OracleMesh only): the
/// refinement's threads (MesherOptions::threads). --sliver-angle (OracleMesh only): the Conforming
/// strategy's picked-point angle (MesherOptions::pickingSliverAngle). --interpolation (OracleMesh
/// only, labels): the label map's LabelInterpolation (default trilinear, as CGAL's). --write: the
/// mesh as points, tetrahedra and materials (writeMesh) for measures the JSON line lacks.
/// --improve (OracleMesh only): its quality step (MesherOptions::improveAngles, default on).
/// --opt remesh (CGAL only): the default optimisers, then CGAL's Tetrahedral_remeshing.
struct Args
{
  std::string kind, input, features;
  double cellSize = 0, facetSize = 0, facetDistance = 0, facetAngle = 25, radiusEdge = 3, edgeSize = 0;
  std::string opt = "default";
  std::string interpolation = "trilinear";
  std::string write;
  bool improve = true;
  double limit = 0;
  unsigned seed = 1;
  int threads = 1;
  double sliverAngle = -1; ///< OracleMesh only: MesherOptions::pickingSliverAngle (< 0: its default)
};

inline Args parseArgs(int argc, char* argv[])
{
  Args a;
  std::vector<std::string> positional;
  for (int i = 1; i < argc; ++i)
  {
    const std::string s = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc)
        throw std::runtime_error(s + " needs a value");
      return argv[++i];
    };
    if (s == "--cell-size") a.cellSize = std::stod(value());
    else if (s == "--facet-size") a.facetSize = std::stod(value());
    else if (s == "--facet-distance") a.facetDistance = std::stod(value());
    else if (s == "--facet-angle") a.facetAngle = std::stod(value());
    else if (s == "--radius-edge") a.radiusEdge = std::stod(value());
    else if (s == "--edge-size") a.edgeSize = std::stod(value());
    else if (s == "--seed") a.seed = static_cast<unsigned>(std::stoul(value()));
    else if (s == "--threads") a.threads = std::stoi(value());
    else if (s == "--sliver-angle") a.sliverAngle = std::stod(value());
    else if (s == "--interpolation") a.interpolation = value();
    else if (s == "--write") a.write = value();
    else if (s == "--improve")
    {
      const std::string v = value();
      if (v != "on" && v != "off")
        throw std::runtime_error("--improve: on or off");
      a.improve = v == "on";
    }
    else if (s == "--opt")
    {
      a.opt = value();
      if (a.opt.rfind("limit:", 0) == 0)
      {
        a.limit = std::stod(a.opt.substr(6));
        a.opt = "limit";
      }
      else if (a.opt != "default" && a.opt != "none" && a.opt != "previous" && a.opt != "remesh")
        throw std::runtime_error("--opt: default, none, previous, remesh or limit:SECONDS");
    }
    else
      positional.push_back(s);
  }
  if (positional.size() < 2 || (positional[0] != "labels" && positional[0] != "surface" && positional[0] != "cad"))
    throw std::runtime_error("usage: <labels|surface|cad> <input> [features] [options]");
  a.kind = positional[0];
  a.input = positional[1];
  if (positional.size() > 2)
    a.features = positional[2];
  if (a.kind == "cad" && a.features.empty())
    throw std::runtime_error("cad needs a features file");
  return a;
}

using Clock = std::chrono::steady_clock;
inline double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

/// CPU seconds of this process (both tools mesh on one thread): unlike wall time, hardly changed
/// by other work on a shared machine.
inline double cpuSeconds()
{
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

/// Peak resident set of this process image: VmHWM from /proc/self/status. getrusage's ru_maxrss
/// is kept across execve on Linux, so a child started by a large parent (Python with VTK loaded)
/// would report the parent's peak; getrusage is the fallback where /proc is missing.
inline double peakRssBytes()
{
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line))
    if (line.rfind("VmHWM:", 0) == 0)
      return std::stod(line.substr(6)) * 1024.0;
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_maxrss * 1024.0;
}

/// Writes "OMTETS <points> <tets>\n", then the points (3 doubles each), the tetrahedra (4 int32
/// each) and their materials (int32 each), little-endian as this machine writes them.
inline void writeMesh(const std::string& path, const omesh::TetMesh& mesh)
{
  std::ofstream out(path, std::ios::binary);
  out << "OMTETS " << mesh.points.size() << " " << mesh.tets.size() << "\n";
  for (const auto& p : mesh.points)
  {
    const double c[3] = { p.x, p.y, p.z };
    out.write(reinterpret_cast<const char*>(c), sizeof c);
  }
  for (const auto& t : mesh.tets)
  {
    const int32_t c[4] = { t[0], t[1], t[2], t[3] };
    out.write(reinterpret_cast<const char*>(c), sizeof c);
  }
  for (size_t i = 0; i < mesh.tets.size(); ++i)
  {
    const int32_t m = i < mesh.tetMaterial.size() ? mesh.tetMaterial[i] : 1;
    out.write(reinterpret_cast<const char*>(&m), sizeof m);
  }
  if (!out)
    throw std::runtime_error(path + ": cannot write the mesh");
}

/// Prints one JSON line with the figures, computed the same way for both tools from `mesh`.
/// `peakRss` is taken by the caller when the mesh is complete (before these checks).
inline void report(const char* tool, const Args& a, const omesh::TetMesh& mesh, double initSeconds,
  double refineSeconds, double perturbSeconds, double exudeSeconds, double optimiseSeconds, double callSeconds,
  double peakRss, double callCpuSeconds, const omesh::FeatureSegments& features, const std::string& extra = "")
{
  double minAngle = 180.0, maxAngle = 0.0, sum = 0.0;
  size_t below10 = 0, outside = 0; // outside: an angle outside [15, 155] degrees
  for (const auto& t : mesh.tets)
  {
    const auto& p = mesh.points;
    const double d = omesh::minDihedralAngle(p[t[0]], p[t[1]], p[t[2]], p[t[3]]);
    const double D = omesh::maxDihedralAngle(p[t[0]], p[t[1]], p[t[2]], p[t[3]]);
    minAngle = std::min(minAngle, d);
    maxAngle = std::max(maxAngle, D);
    sum += d;
    below10 += d < 10.0;
    outside += d < 15.0 || D > 155.0;
  }
  omesh::ValidityThresholds th;
  th.segmentsRequired = false; // coverage is reported on its own
  const omesh::MeshValidity v = omesh::checkMeshValidity(mesh, {}, th);
  double coverage = -1;
  if (!features.empty())
    coverage = omesh::featureCoverage(omesh::locateFeatureSegments(mesh, features), features);
  std::ostringstream o;
  o.precision(6);
  o << "{\"tool\": \"" << tool << "\", \"kind\": \"" << a.kind << "\", \"opt\": \"" << a.opt << "\", \"limit\": " << a.limit
    << ", \"tets\": " << mesh.tets.size() << ", \"vertices\": " << mesh.points.size()
    << ", \"setup\": " << initSeconds << ", \"refine\": " << refineSeconds << ", \"perturb\": " << perturbSeconds
    << ", \"exude\": " << exudeSeconds << ", \"optimise\": " << optimiseSeconds << ", \"call\": " << callSeconds << ", \"call_cpu\": " << callCpuSeconds
    << ", \"peak_rss\": " << peakRss << ", \"min_dihedral\": " << (mesh.tets.empty() ? 0.0 : minAngle)
    << ", \"mean_min_dihedral\": " << (mesh.tets.empty() ? 0.0 : sum / mesh.tets.size())
    << ", \"max_dihedral\": " << maxAngle << ", \"outside_15_155\": " << outside
    << ", \"tets_below_10\": " << below10 << ", \"defects\": " << v.defects()
    << ", \"duplicates\": " << v.duplicateVertices << ", \"flat\": " << v.flatTetrahedra
    << ", \"micro\": " << v.microTetrahedra << ", \"inverted\": " << v.invertedTetrahedra
    << ", \"non_manifold\": " << v.nonManifoldFaces << ", \"coverage\": " << coverage << extra << "}";
  if (!a.write.empty())
    writeMesh(a.write, mesh);
  std::printf("%s\n", o.str().c_str());
  std::fflush(stdout);
}
}
