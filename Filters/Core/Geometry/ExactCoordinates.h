// SPDX-License-Identifier: GPL-3.0-or-later
// A point's coordinates bit for bit, as a hash key: finds the same point again in another
// triangulation (a copy of a complex, the parallel one) without a tolerance.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <functional>

namespace omesh
{
using ExactCoordinates = std::array<std::uint64_t, 3>;

inline ExactCoordinates exactCoordinates(double x, double y, double z)
{
  ExactCoordinates c{};
  const double xyz[3] = { x, y, z };
  for (int a = 0; a < 3; ++a)
    std::memcpy(&c[a], &xyz[a], sizeof(double));
  return c;
}

struct ExactCoordinatesHash
{
  std::size_t operator()(const ExactCoordinates& c) const
  {
    return std::hash<std::uint64_t>()(c[0] ^ (c[1] * 0x9e3779b97f4a7c15ull) ^ (c[2] * 0xc2b2ae3d27d4eb4full));
  }
};
}
