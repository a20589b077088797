// Thread count of the harness's parallel loops (OpenMP, when the build has it).
//
// Results never depend on the thread count: every parallel kernel in core either writes
// disjoint outputs (node-centric gathers, per-node updates) or combines partial results in an
// order fixed by the data alone (chunks of kChunk items, reduced in chunk order). A run's
// state hash is therefore the same with 1 or N threads; tests/core/test_parallel.cpp checks it.
//
// Default: 1 thread, unless the environment variable HARNESS_THREADS holds an integer >= 1
// (read once, on first use). `harness run --threads N` and `harness bench` call set_threads().
#pragma once

#include <cstddef>

namespace harness {

// Threads the parallel loops use (>= 1).
int threads();
// Sets it; n < 1 is taken as 1. Not meant to be called while a parallel loop runs.
void set_threads(int n);

// Testing aid: when > 0, replaces every loop's `min_items` below, so that tests can run the
// parallel code paths on small worlds (set_parallel_grain(1)); 0 restores the defaults.
void set_parallel_grain(std::size_t items_per_thread);
std::size_t parallel_grain();

// Threads worth using for a loop of n cheap items: 1 below `min_items` per extra thread
// (a parallel region costs a few microseconds), else threads(). Only ever changes speed.
inline int threads_for(std::size_t n, std::size_t min_items = 8192) {
  const int t = threads();
  if (t <= 1) return 1;
  if (const std::size_t g = parallel_grain()) min_items = g;
  if (n < 2 * min_items) return 1;
  const std::size_t most = n / min_items;
  return most < static_cast<std::size_t>(t) ? static_cast<int>(most) : t;
}

// Item range [begin, end) of part p of n items split into `parts` contiguous parts of nearly
// equal size (the first n % parts parts one item longer).
inline void split_range(std::size_t n, int parts, int p, std::size_t& begin, std::size_t& end) {
  const std::size_t q = n / static_cast<std::size_t>(parts), r = n % static_cast<std::size_t>(parts);
  const std::size_t up = static_cast<std::size_t>(p);
  begin = up * q + (up < r ? up : r);
  end = begin + q + (up < r ? 1 : 0);
}

}  // namespace harness
