// SPDX-License-Identifier: GPL-3.0-or-later
// Fuzz harness: hierarchical oracles of up to six domains of every kind (spheres, boxes,
// cylinders, half-spaces, with transforms; small surfaces and label maps), cut or not, queried at
// arbitrary points and segments. Checks what the mesher relies on: intersect() starts with the
// material at a, reports a change only to another material, at t in [0, 1], and finds none only
// when b has a's material.
#include "BoxDomain.h"
#include "CylinderDomain.h"
#include "FuzzInput.h"
#include "HalfSpaceDomain.h"
#include "HierarchicalOracle.h"
#include "InputError.h"
#include "LabelMapDomain.h"
#include "SphereDomain.h"
#include "SurfaceDomain.h"

#include <algorithm>
#include <cmath>
#include <memory>

using namespace omesh;

namespace
{
std::shared_ptr<Domain> makeDomain(fuzz::Input& in, int material)
{
  const uint8_t kind = in.byte();
  std::shared_ptr<ImplicitShapeDomain> shape;
  switch (kind % 6)
  {
    case 0:
      shape = std::make_shared<SphereDomain>(in.point(), in.coordinate(), material);
      break;
    case 1:
      shape = std::make_shared<BoxDomain>(in.point(), in.point(), material);
      break;
    case 2:
    {
      const Vec3 c = in.point(), a = in.point();
      const double r = in.coordinate();
      const double h = (kind & 8) ? INFINITY : in.coordinate();
      shape = std::make_shared<CylinderDomain>(c, a, r, h, material);
      break;
    }
    case 3:
      shape = std::make_shared<HalfSpaceDomain>(in.point(), in.point(), material);
      break;
    case 4: // a tetrahedron or an octahedron-ish closed surface
    {
      TriangleSurface s;
      const Vec3 c = in.point();
      const double r = in.coordinate();
      s.points = { c + Vec3{ r, 0, 0 }, c + Vec3{ -r, 0, 0 }, c + Vec3{ 0, r, 0 }, c + Vec3{ 0, -r, 0 },
        c + Vec3{ 0, 0, r }, c + Vec3{ 0, 0, -r } };
      s.triangles = { { 0, 2, 4 }, { 2, 1, 4 }, { 1, 3, 4 }, { 3, 0, 4 }, { 2, 0, 5 }, { 1, 2, 5 }, { 3, 1, 5 },
        { 0, 3, 5 } };
      for (auto& p : s.points) // jiggle a few vertices
        if (in.byte() & 1)
          p = p + Vec3{ in.coordinate() / 8, in.coordinate() / 8, in.coordinate() / 8 };
      SurfaceOptions opts;
      opts.insideTest = (kind & 16) ? InsideTest::WindingNumber : InsideTest::Closed;
      opts.allowSelfIntersections = kind & 32;
      auto d = std::make_shared<SurfaceDomain>(s, material, "surface", opts);
      d->setCut(kind & 64);
      return d;
    }
    default:
    {
      std::array<int, 3> dims{ 1 + in.byte() % 4, 1 + in.byte() % 4, 1 + in.byte() % 4 };
      std::vector<int> labels(static_cast<size_t>(dims[0]) * dims[1] * dims[2]);
      for (int& l : labels)
        l = in.byte() % 4;
      std::array<double, 9> dir{ 1, 0, 0, 0, 1, 0, 0, 0, 1 };
      if (kind & 8)
        for (double& v : dir)
          v = in.coordinate();
      const AffineMap map = LabelMapDomain::pointCenteredWorldToVoxel(in.point(), in.point(), dir);
      auto d = std::make_shared<LabelMapDomain>(dims, labels, map, 0, "labels",
        !(kind & 16) ? LabelInterpolation::Nearest
          : (kind & 32) ? LabelInterpolation::Smooth // (32: the surfaces' bit, free here)
                        : LabelInterpolation::Trilinear);
      d->setCut(kind & 64);
      return d;
    }
  }
  if (kind & 128) // a transform: world -> local
  {
    std::array<double, 12> m{};
    for (double& v : m)
      v = in.coordinate();
    shape->setWorldToLocal(AffineMap(m));
  }
  shape->setCut(kind & 64);
  return shape;
}
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
  fuzz::Input in(data, size);
  HierarchicalOracle oracle;
  const int numDomains = 1 + in.byte() % 6;
  try
  {
    for (int d = 0; d < numDomains; ++d)
      oracle.add(makeDomain(in, d + 1));
    (void)oracle.bounds();
  }
  catch (const InputError& e)
  {
    FUZZ_CHECK(e.what()[0] != '\0');
    if (oracle.empty())
      return 0;
  }
  std::vector<Vec3> queries;
  while (!in.empty() && queries.size() < 64)
    queries.push_back(in.point());
  if (queries.size() < 2)
    queries = { { 0, 0, 0 }, { 1, 2, 3 } };
  const std::vector<int> materials = oracle.materials();
  for (size_t q = 0; q + 1 < queries.size(); ++q)
  {
    const Vec3& a = queries[q];
    const Vec3& b = queries[q + 1];
    const int ma = oracle.material(a);
    FUZZ_CHECK(ma == kOutside || std::binary_search(materials.begin(), materials.end(), ma));
    const Intersection x = oracle.intersect(a, b);
    FUZZ_CHECK(x.materialBefore == ma);
    if (x.found)
    {
      FUZZ_CHECK(x.t >= 0.0 && x.t <= 1.0);
      FUZZ_CHECK(x.materialAfter != x.materialBefore);
    }
    else
      FUZZ_CHECK(oracle.material(b) == ma);
  }
  return 0;
}
