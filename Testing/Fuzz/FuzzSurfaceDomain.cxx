// SPDX-License-Identifier: GPL-3.0-or-later
// Fuzz harness: arbitrary triangle soups -> TriangleSurface validation -> SurfaceDomain (and its
// queries when the surface is accepted). Bad input must end in an InputError, never a crash, and
// the grid shortcut must agree with the exact inside test.
#include "FuzzInput.h"
#include "InputError.h"
#include "SurfaceDomain.h"

#include <cmath>

using namespace omesh;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
  fuzz::Input in(data, size);
  const uint8_t options = in.byte();
  TriangleSurface s;
  const int numPoints = in.byte() % 48;
  for (int i = 0; i < numPoints; ++i)
    s.points.push_back(in.point());
  const int numTriangles = in.byte() % 96;
  for (int t = 0; t < numTriangles; ++t)
  {
    std::array<int, 3> tri{};
    for (int& v : tri)
    {
      const uint8_t b = in.byte();
      v = b == 255 ? in.int32() : static_cast<int>(b % (numPoints + 1)); // numPoints: out of range
    }
    s.triangles.push_back(tri);
  }
  SurfaceOptions opts;
  opts.allowSelfIntersections = options & 1;
  opts.insideTest = (options & 2) ? InsideTest::WindingNumber : InsideTest::Closed;
  std::unique_ptr<SurfaceDomain> domain;
  try
  {
    domain = std::make_unique<SurfaceDomain>(s, 1, "fuzz", opts);
  }
  catch (const InputError& e)
  {
    FUZZ_CHECK(e.what()[0] != '\0');
    return 0;
  }
  const BoundingBox box = domain->bounds();
  FUZZ_CHECK(!box.empty());
  (void)domain->volume();
  (void)domain->numberOfTriangles();
  // queries: the surface's own points and triangle centroids, then points from the input
  std::vector<Vec3> queries = s.points;
  for (const auto& t : s.triangles)
    queries.push_back((1.0 / 3.0) * (s.points[t[0]] + s.points[t[1]] + s.points[t[2]]));
  while (!in.empty() && queries.size() < 256)
    queries.push_back(in.point());
  std::vector<double> ts;
  for (size_t q = 0; q < queries.size(); ++q)
  {
    const Vec3& p = queries[q];
    const int m = domain->material(p);
    FUZZ_CHECK(m == 1 || m == kOutside);
    FUZZ_CHECK((m == 1) == domain->containsExact(p)); // the grid never changes an answer
    ts.clear();
    domain->crossings(p, queries[(q * 7 + 1) % queries.size()], ts);
    for (double t : ts)
      FUZZ_CHECK(t >= 0.0 && t <= 1.0);
  }
  return 0;
}
