// An undirected edge (a, b) as one sortable 64-bit key, the smaller index in the high half: how
// the surface checks (mesh.cpp) and the model generators (shapes/) find shared edges by sorting.
#pragma once

#include "core/types.hpp"

#include <cstdint>
#include <utility>

namespace harness {

inline std::uint64_t edge_key(int a, int b) {
  if (a > b) std::swap(a, b);
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) | static_cast<std::uint32_t>(b);
}

// The edge of a key, smaller index first.
inline Edge key_edge(std::uint64_t k) { return {static_cast<int>(k >> 32), static_cast<int>(k & 0xffffffffu)}; }

}  // namespace harness
