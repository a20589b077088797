#include "core/parallel.hpp"

#include <cstdlib>


namespace harness {

namespace {

int env_threads() {
  const char* s = std::getenv("HARNESS_THREADS");
  if (!s || !*s) return 1;
  char* end = nullptr;
  const long v = std::strtol(s, &end, 10);
  if (*end != '\0' || v < 1) return 1;
  return v > 1024 ? 1024 : static_cast<int>(v);
}

int& setting() {
  static int n = env_threads();
  return n;
}

std::size_t& grain() {
  static std::size_t g = 0;
  return g;
}

}  // namespace

int threads() { return setting(); }

void set_threads(int n) { setting() = n < 1 ? 1 : n; }

void set_parallel_grain(std::size_t items_per_thread) { grain() = items_per_thread; }

std::size_t parallel_grain() { return grain(); }

}  // namespace harness
