// SPDX-License-Identifier: GPL-3.0-or-later
// Refusing work the machine cannot hold, before it starts: an error naming the sizes, not
// std::bad_alloc or the OOM killer later.
#pragma once

#include <string>

namespace omesh
{
/// Bytes this process may still allocate: the system's available memory (MemAvailable), capped by
/// the address-space limit (ulimit -v).
double availableMemory();

/// Throws InputError before allocating `count` items of `bytesEach` bytes when they would need more
/// than availableMemory(): "who: what (count) would need X GB (B bytes each); Y GB available".
void checkMemory(const std::string& who, const std::string& what, double count, double bytesEach);
}
