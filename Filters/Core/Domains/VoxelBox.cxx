// SPDX-License-Identifier: GPL-3.0-or-later
#include "VoxelBox.h"

#include <limits>

namespace omesh
{
/// Running maximum of `values` over the cube of half-width r voxels (clamped at the box): per line,
/// van Herk and Gil-Werman's two running maxima in blocks of 2r + 1 (three comparisons a voxel
/// whatever r).
void runningMaximum(const VoxelBox& box, int r, std::vector<float>& values)
{
  const size_t w = 2 * static_cast<size_t>(r) + 1;
  for (int axis = 0; axis < 3; ++axis)
    forEachLine(box, axis, [&](size_t start, size_t stride, int n, LineScratch& s) {
      const size_t m = static_cast<size_t>(n) + 2 * static_cast<size_t>(r); // the line padded with -inf
      for (std::vector<double>* buffer : { &s.a, &s.b, &s.c })
        if (buffer->size() < m)
          buffer->resize(m);
      double *line = s.a.data(), *ahead = s.b.data(), *behind = s.c.data();
      for (size_t j = 0; j < m; ++j)
        line[j] = j >= static_cast<size_t>(r) && j < static_cast<size_t>(r + n)
          ? static_cast<double>(values[start + stride * (j - r)])
          : -std::numeric_limits<double>::infinity();
      for (size_t first = 0; first < m; first += w) // per block: from its start, and to its end
      {
        const size_t end = std::min(first + w, m);
        behind[first] = line[first];
        for (size_t j = first + 1; j < end; ++j)
          behind[j] = std::max(behind[j - 1], line[j]);
        ahead[end - 1] = line[end - 1];
        for (size_t j = end - 1; j-- > first;)
          ahead[j] = std::max(ahead[j + 1], line[j]);
      }
      for (int q = 0; q < n; ++q) // the window [q, q + 2r] of the padded line
        values[start + stride * q] = static_cast<float>(std::max(ahead[q], behind[q + 2 * r]));
    });
}

}
