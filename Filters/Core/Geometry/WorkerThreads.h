// SPDX-License-Identifier: GPL-3.0-or-later
// How many threads the core's parallel loops (TBB) may use during one call, and its one loop shape.
#pragma once

#include <cstddef>
#include <functional>

namespace omesh
{
/// Runs `work` with every parallel loop inside it (a label map's smoothing, the output's passes)
/// on at most `threads` threads: 1 = the calling thread alone, 0 = every core. A run asked for one
/// thread then uses one (a batch of one-thread runs, one per core, does not oversubscribe the
/// machine). Exceptions thrown by `work` reach the caller.
void runOnThreads(int threads, const std::function<void()>& work);

/// How forEachChunk splits n items: chunks of at least `smallest` items, at most 64 chunks
/// (1 for n = 0). A function of n alone, not of the threads.
std::size_t chunkCount(std::size_t n, std::size_t smallest);

/// Calls body(chunk, begin, end) for each of `chunks` consecutive ranges covering [0, n), in
/// parallel on the threads runOnThreads allows (all of them outside it). Results kept per chunk
/// and merged in chunk order are the same on any number of threads (sums in the same order). An
/// exception from body reaches the caller (the other chunks are cancelled).
void forEachChunk(std::size_t n, std::size_t chunks,
  const std::function<void(std::size_t chunk, std::size_t begin, std::size_t end)>& body);
}
