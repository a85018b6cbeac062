// SPDX-License-Identifier: GPL-3.0-or-later
// Private to Meshing/OracleMesher.cxx (the sequential Mesh_3 translation unit) and the headers of
// its phases: the sequential triangulation's types and the run's clocks.
#pragma once

#include "MeshTriangulation3.h"

#include <CGAL/Mesh_3/Dump_c3t3.h>

#include <chrono>
#include <ctime>

namespace omesh::cgal::sequential
{
using Types = MeshTriangulation3<CGAL::Sequential_tag>;
using Tr = Types::Tr;
using C3t3 = Types::C3t3;
using Criteria = Types::Criteria;
using Clock = std::chrono::steady_clock;

/// Wall seconds since `since`.
inline double seconds(Clock::time_point since)
{
  return std::chrono::duration<double>(Clock::now() - since).count();
}

/// CPU seconds of the calling thread.
inline double threadCpu()
{
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}
}

namespace CGAL
{
// Before some errors CGAL dumps the complex into the working directory (dump-bug.mesh,
// dump-bug.binary.cgal): never into a user's.
template <>
struct Dump_c3t3<omesh::cgal::sequential::C3t3, true>
{
  void dump_c3t3(const omesh::cgal::sequential::C3t3&, std::string) const {}
};
template <>
struct Dump_c3t3<omesh::cgal::sequential::C3t3, false>
{
  void dump_c3t3(const omesh::cgal::sequential::C3t3&, std::string) const {}
};
}
