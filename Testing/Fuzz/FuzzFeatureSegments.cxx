// SPDX-License-Identifier: GPL-3.0-or-later
// Fuzz harness: feature lines as users give them (repeated points and segments, overlaps,
// crossings, NaN, indices out of range) -> mergeFeatureSegments -> FeatureSegments::validate ->
// conformSegments, as the mesher runs them. Bad input must end in an InputError.
#include "FeatureMerge.h"
#include "FuzzInput.h"
#include "HierarchicalOracle.h"
#include "InputError.h"
#include "SegmentConformation.h"
#include "SphereDomain.h"

using namespace omesh;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
  fuzz::Input in(data, size);
  const uint8_t options = in.byte();
  FeatureSegments f;
  const int numPoints = in.byte() % 40;
  for (int i = 0; i < numPoints; ++i)
    f.points.push_back(in.point());
  const int numSegments = in.byte() % 64;
  for (int s = 0; s < numSegments; ++s)
  {
    std::array<int, 2> seg{};
    for (int& v : seg)
    {
      const uint8_t b = in.byte();
      v = b == 255 ? in.int32() : static_cast<int>(b % (numPoints + 1));
    }
    f.segments.push_back(seg);
  }
  if (!(options & 1))
  {
    const FeatureMergeCounts counts = mergeFeatureSegments(f);
    // after a merge every segment still refers to a point when the input did
    (void)counts;
  }
  HierarchicalOracle oracle;
  oracle.add(std::make_shared<SphereDomain>(Vec3{ 0, 0, 0 }, 4.0, 1));
  const double radiusEdge = (options & 2) ? in.coordinate() : 2.0;
  try
  {
    const std::vector<std::string> warnings = f.validate(oracle, radiusEdge);
    (void)warnings;
  }
  catch (const InputError& e)
  {
    FUZZ_CHECK(e.what()[0] != '\0');
    return 0;
  }
  const double angle = f.smallestAngle();
  FUZZ_CHECK(angle >= 0.0 && angle <= 180.0);
  const std::vector<bool> star = f.starVertices();
  FUZZ_CHECK(star.size() == f.points.size());
  std::vector<std::string> warnings;
  const double edgeSize = (options & 4) ? std::abs(in.coordinate()) : 0.0;
  const SegmentSet set = conformSegments(f, edgeSize, 20000, warnings);
  for (const auto& sub : set.subs)
  {
    FUZZ_CHECK(sub[0] >= 0 && sub[0] < static_cast<int>(set.points.size()));
    FUZZ_CHECK(sub[1] >= 0 && sub[1] < static_cast<int>(set.points.size()));
  }
  return 0;
}
