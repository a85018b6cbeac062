// SPDX-License-Identifier: GPL-3.0-or-later
// The thread limit of one call and the chunked loops the passes over a finished mesh use.
#include "WorkerThreads.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <mutex>
#include <set>
#include <stdexcept>
#include <thread>
#include <vector>

namespace
{
/// The threads that ran forEachChunk's chunks (each chunk sleeps a little, so that every thread
/// allowed gets some when it may).
std::set<std::thread::id> threadsUsed(std::size_t chunks)
{
  std::mutex m;
  std::set<std::thread::id> ids;
  omesh::forEachChunk(chunks * 10, chunks, [&](std::size_t, std::size_t, std::size_t) {
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
    std::lock_guard<std::mutex> lock(m);
    ids.insert(std::this_thread::get_id());
  });
  return ids;
}
}

TEST(WorkerThreads, OneThreadMeansTheCallingThreadAlone)
{
  std::set<std::thread::id> ids;
  omesh::runOnThreads(1, [&] { ids = threadsUsed(64); });
  ASSERT_EQ(ids.size(), 1u);
  EXPECT_EQ(*ids.begin(), std::this_thread::get_id());
}

TEST(WorkerThreads, NThreadsAtMost)
{
  std::set<std::thread::id> ids;
  omesh::runOnThreads(2, [&] { ids = threadsUsed(64); });
  EXPECT_GE(ids.size(), 1u);
  EXPECT_LE(ids.size(), 2u);
  if (std::thread::hardware_concurrency() >= 2)
    EXPECT_EQ(ids.size(), 2u); // 64 chunks of 2 ms: a second thread of the arena takes some
}

TEST(WorkerThreads, ChunksCoverTheRangeOnceInOrderWhateverTheThreads)
{
  for (std::size_t n : { std::size_t{ 0 }, std::size_t{ 1 }, std::size_t{ 63 }, std::size_t{ 64 }, std::size_t{ 1000 }, std::size_t{ 100003 } })
    for (int threads : { 1, 2, 0 })
    {
      const std::size_t chunks = omesh::chunkCount(n, 100);
      EXPECT_GE(chunks, 1u);
      EXPECT_LE(chunks, 64u);
      std::vector<std::pair<std::size_t, std::size_t>> bounds(chunks, { 1, 0 });
      std::vector<std::atomic<int>> seen(n);
      omesh::runOnThreads(threads, [&] {
        omesh::forEachChunk(n, chunks, [&](std::size_t c, std::size_t begin, std::size_t end) {
          bounds[c] = { begin, end };
          for (std::size_t i = begin; i < end; ++i)
            ++seen[i];
        });
      });
      std::size_t next = 0;
      for (const auto& [begin, end] : bounds) // consecutive, in chunk order
      {
        EXPECT_EQ(begin, next) << "n " << n << " threads " << threads;
        EXPECT_LE(begin, end);
        next = end;
      }
      EXPECT_EQ(next, n);
      for (std::size_t i = 0; i < n; ++i)
        ASSERT_EQ(seen[i].load(), 1) << "item " << i << " of " << n;
    }
}

TEST(WorkerThreads, AnExceptionReachesTheCaller)
{
  EXPECT_THROW(omesh::runOnThreads(2, [] {
    omesh::forEachChunk(1000, 10, [](std::size_t c, std::size_t, std::size_t) {
      if (c == 7)
        throw std::runtime_error("chunk 7");
    });
  }),
    std::runtime_error);
}
