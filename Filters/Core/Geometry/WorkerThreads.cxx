// SPDX-License-Identifier: GPL-3.0-or-later
#include "WorkerThreads.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>
#include <tbb/task_arena.h>

#include <algorithm>

namespace omesh
{
void runOnThreads(int threads, const std::function<void()>& work)
{
  tbb::task_arena arena(threads > 0 ? threads : static_cast<int>(tbb::task_arena::automatic));
  arena.execute(work);
}

std::size_t chunkCount(std::size_t n, std::size_t smallest)
{
  return std::clamp<std::size_t>(n / std::max<std::size_t>(smallest, 1), 1, 64);
}

void forEachChunk(std::size_t n, std::size_t chunks,
  const std::function<void(std::size_t chunk, std::size_t begin, std::size_t end)>& body)
{
  chunks = std::max<std::size_t>(chunks, 1);
  const auto bound = [n, chunks](std::size_t c) { return n / chunks * c + std::min(c, n % chunks); };
  if (chunks == 1)
  {
    body(0, 0, n);
    return;
  }
  tbb::parallel_for(
    tbb::blocked_range<std::size_t>(0, chunks, 1),
    [&](const tbb::blocked_range<std::size_t>& r) {
      for (std::size_t c = r.begin(); c != r.end(); ++c)
        body(c, bound(c), bound(c + 1));
    },
    tbb::simple_partitioner());
}
}
