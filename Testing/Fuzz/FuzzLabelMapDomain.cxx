// SPDX-License-Identifier: GPL-3.0-or-later
// Fuzz harness: label maps of any dims, spacing, origin, direction and data, both conventions and
// both interpolations. Bad input must end in an InputError; accepted maps answer queries with
// their own materials and crossing parameters in [0, 1].
#include "FuzzInput.h"
#include "InputError.h"
#include "LabelMapDomain.h"

#include <algorithm>
#include <memory>

using namespace omesh;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
  fuzz::Input in(data, size);
  const uint8_t options = in.byte();
  std::array<int, 3> dims{};
  for (int& d : dims)
  {
    const uint8_t b = in.byte();
    d = b >= 250 ? in.int32() : b % 7; // any int now and then (0 and negative included)
  }
  Vec3 origin = in.point();
  Vec3 spacing{ 1, 1, 1 };
  if (options & 4)
    spacing = in.point();
  std::array<double, 9> direction{ 1, 0, 0, 0, 1, 0, 0, 0, 1 };
  if (options & 8)
    for (double& d : direction)
      d = in.coordinate();
  const int background = (options & 16) ? static_cast<int>(in.byte()) - 2 : 0;
  // labels: as many as the input holds, up to what dims ask (or not: a size mismatch is an error)
  std::vector<int> labels;
  const size_t wanted = static_cast<size_t>(std::max(dims[0], 0)) * std::max(dims[1], 0) * std::max(dims[2], 0);
  const size_t count = (options & 32) ? in.byte() : std::min<size_t>(wanted, 4096);
  for (size_t i = 0; i < count; ++i)
    labels.push_back(static_cast<int>(in.byte() % 6) - 1 + ((options & 64) ? 70000 * (i % 2) : 0));
  const LabelInterpolation interp = !(options & 1) ? LabelInterpolation::Nearest
    : (options & 128)                              ? LabelInterpolation::Smooth
                                                   : LabelInterpolation::Trilinear;
  std::unique_ptr<LabelMapDomain> domain;
  try
  {
    const AffineMap map = (options & 2) ? LabelMapDomain::cellCenteredWorldToVoxel(origin, spacing, direction)
                                        : LabelMapDomain::pointCenteredWorldToVoxel(origin, spacing, direction);
    domain = std::make_unique<LabelMapDomain>(dims, labels, map, background, "fuzz", interp);
  }
  catch (const InputError& e)
  {
    FUZZ_CHECK(e.what()[0] != '\0');
    return 0;
  }
  const std::vector<int> materials = domain->materials();
  const BoundingBox box = domain->bounds();
  (void)domain->voxelCounts();
  std::vector<Vec3> queries{ box.min, box.max, 0.5 * (box.min + box.max), origin };
  while (!in.empty() && queries.size() < 128)
    queries.push_back(in.point());
  std::vector<double> ts;
  for (size_t q = 0; q < queries.size(); ++q)
  {
    const int m = domain->material(queries[q]);
    FUZZ_CHECK(m == kOutside || std::binary_search(materials.begin(), materials.end(), m));
    ts.clear();
    domain->crossings(queries[q], queries[(q * 5 + 1) % queries.size()], ts);
    for (double t : ts)
      FUZZ_CHECK(t >= 0.0 && t <= 1.0);
  }
  return 0;
}
