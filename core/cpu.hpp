// Instruction sets: the one place that asks the processor what it can run, and the override
// that picks which compiled version of the SIMD kernels (core/simd/kernels.hpp) runs.
//
// Levels, each including the ones before it:
//   scalar  plain C++ (the baseline of the build; the only level off x86-64)
//   avx     AVX: four doubles per instruction
//   avx2    AVX2: as avx, and eight-lane integer operations
//   avx512  AVX-512 F and VL: eight doubles per instruction
// Every level gives the same results to the bit (the kernels do each lane's scalar operations,
// exact integer operations or exact min/max; see core/simd/kernels.hpp), so the level only
// changes speed: a run's state hash is the same with any of them.
//
// The active level is the best one the processor (and OS) supports, unless the environment
// variable HARNESS_ISA names one (scalar, avx, avx2, avx512; read once, at start-up) or a test
// calls set_isa(). A HARNESS_ISA word that is unknown, or names a level this processor cannot
// run, is rejected at start-up: any program linking core prints one line,
// "harness: error: HARNESS_ISA: ...", and exits with status 2 before doing anything else.
//
// expm1 is not a kernel path: the exponential spring law takes glibc's vector expm1 (libmvec)
// whenever the build has it and the processor has AVX2, whatever the active level, scalar
// included (core/springs.hpp). libmvec's and std::expm1's last bits differ, so the state hashes
// of scenes with exponential springs (tests/golden/state_hashes.json) assume x86-64 with AVX2
// and libmvec; on such a machine every level gives them.
#pragma once

#include <string>

namespace harness {

enum class Isa { scalar, avx, avx2, avx512 };

// Every level, lowest first.
constexpr Isa kAllIsas[] = {Isa::scalar, Isa::avx, Isa::avx2, Isa::avx512};

const char* to_string(Isa isa);

// The best level this processor supports and this build has kernels for.
Isa cpu_isa();
// Whether the processor can run level `isa` (isa <= cpu_isa()).
bool isa_supported(Isa isa);

// The word as a level: "scalar", "avx", "avx2" or "avx512". Throws InputError(where, ...) for an
// unknown word, or a level above `best` (the processor's, unless a test says otherwise).
Isa parse_isa(const std::string& word, const std::string& where = "HARNESS_ISA", Isa best = cpu_isa());

// The level the kernels run at: set_isa's, else HARNESS_ISA's, else cpu_isa().
Isa isa();
// Forces a level (tests: every path on one machine). Throws std::invalid_argument when the
// processor cannot run it. Not meant to be called while a kernel runs.
void set_isa(Isa isa);
// Back to the default: HARNESS_ISA's level, else cpu_isa().
void reset_isa();

}  // namespace harness
