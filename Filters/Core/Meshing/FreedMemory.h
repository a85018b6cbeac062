// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

namespace omesh
{
/// Hands memory the process freed back to the system where the C library keeps it (glibc keeps
/// freed heap pages mapped). Called once the triangulation is released: its pages would otherwise
/// stay resident under everything allocated after it (the quality step, the checks, the VTK
/// arrays), and the process's peak would be the triangulation plus all of those. A no-op on other
/// C libraries.
void returnFreedMemory();
}
