// The state hash of a run (summary.json state_hash, tests/golden/state_hashes.json): 64-bit
// FNV-1a over the bytes of every node's position, then every node's velocity, as 16 hex digits.
// Equal hashes: bit-identical states.
#pragma once

#include "core/world.hpp"

#include <string>

namespace harness {

std::string state_hash(const World& w);

}  // namespace harness
