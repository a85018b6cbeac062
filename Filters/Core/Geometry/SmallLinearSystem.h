// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <algorithm>
#include <cmath>
#include <utility>

namespace omesh
{
/// Solves the N x N system in the first N columns of m for the right-hand side in its last one
/// (Gaussian elimination, partial pivoting; m is overwritten). False when singular.
template <int N>
bool solveLinear(double (&m)[N][N + 1], double (&c)[N])
{
  for (int col = 0; col < N; ++col)
  {
    int pivot = col;
    for (int r = col + 1; r < N; ++r)
      if (std::abs(m[r][col]) > std::abs(m[pivot][col]))
        pivot = r;
    std::swap(m[col], m[pivot]);
    if (!(std::abs(m[col][col]) > 0))
      return false;
    for (int r = col + 1; r < N; ++r)
    {
      const double f = m[r][col] / m[col][col];
      for (int k = col; k <= N; ++k)
        m[r][k] -= f * m[col][k];
    }
  }
  for (int i = N - 1; i >= 0; --i)
  {
    double sum = m[i][N];
    for (int k = i + 1; k < N; ++k)
      sum -= m[i][k] * c[k];
    c[i] = sum / m[i][i];
  }
  return true;
}
}
