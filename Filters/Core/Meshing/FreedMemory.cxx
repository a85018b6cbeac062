// SPDX-License-Identifier: GPL-3.0-or-later
#include "FreedMemory.h"

#include <cstdlib> // defines __GLIBC__ on glibc

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace omesh
{
void returnFreedMemory()
{
#if defined(__GLIBC__)
  malloc_trim(0);
#endif
}
}
