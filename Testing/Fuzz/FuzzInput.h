// SPDX-License-Identifier: GPL-3.0-or-later
// Shared by the fuzz harnesses: turns libFuzzer's bytes into numbers that hit the interesting
// cases often (small grid coordinates that coincide, collinear and coplanar points) and now and then
// any double at all (NaN, infinities, 1e300, denormals).
#pragma once

#include "Vec3.h"

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace omesh::fuzz
{
/// Checks an invariant of the code under test; a violation is a finding (abort, so libFuzzer keeps
/// the input and the replay test fails).
#define FUZZ_CHECK(cond)                                                                           \
  do                                                                                               \
  {                                                                                                \
    if (!(cond))                                                                                   \
    {                                                                                              \
      std::fprintf(stderr, "%s:%d: invariant violated: %s\n", __FILE__, __LINE__, #cond);          \
      std::abort();                                                                                \
    }                                                                                              \
  } while (0)

class Input
{
public:
  Input(const uint8_t* data, size_t size)
    : data_(data)
    , size_(size)
  {
  }
  bool empty() const { return pos_ >= size_; }
  size_t remaining() const { return pos_ < size_ ? size_ - pos_ : 0; }

  uint8_t byte()
  {
    return pos_ < size_ ? data_[pos_++] : 0;
  }
  /// A little-endian integer of `bytes` bytes (missing bytes are 0).
  uint64_t bits(int bytes)
  {
    uint64_t v = 0;
    for (int i = 0; i < bytes; ++i)
      v |= static_cast<uint64_t>(byte()) << (8 * i);
    return v;
  }
  int32_t int32() { return static_cast<int32_t>(static_cast<uint32_t>(bits(4))); }
  double rawDouble()
  {
    const uint64_t b = bits(8);
    double d;
    std::memcpy(&d, &b, sizeof d);
    return d;
  }
  /// Mostly multiples of 1/4 in [-8, 8] (coincidences and degeneracies), sometimes any double.
  double coordinate()
  {
    const uint8_t tag = byte();
    if (tag < 240)
      return (static_cast<int>(tag % 65) - 32) / 4.0;
    switch (tag & 3)
    {
      case 0:
        return rawDouble();
      case 1:
        return (static_cast<int>(byte()) - 128) * 1e-9; // tiny offsets from the grid
      case 2:
        return static_cast<double>(int32()) * 1e3; // far away
      default:
        return (static_cast<int>(byte()) - 128) / 64.0 + (static_cast<int>(byte()) - 128) * 1e-12;
    }
  }
  Vec3 point() { return { coordinate(), coordinate(), coordinate() }; }

private:
  const uint8_t* data_;
  size_t size_;
  size_t pos_ = 0;
};
}
