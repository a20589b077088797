// Shared by the fuzz targets (tests/fuzz/fuzz_*.cpp). Each target defines
// LLVMFuzzerTestOneInput: built with clang -fsanitize=fuzzer (CMake option HARNESS_FUZZ,
// scripts/fuzz.sh) it is fuzzed by libFuzzer; built with any compiler and replay_main.cpp it
// replays the committed corpus under ctest (tests fuzz:replay_*).
//
// Contract checked: bad input throws harness::InputError and nothing else. Any other exception
// escapes LLVMFuzzerTestOneInput (std::terminate, a crash libFuzzer reports); a broken
// invariant of an accepted input calls fuzz_check_failed (abort).
#pragma once

#include <cstdio>
#include <cstdlib>
#include <string>

// With HARNESS_FUZZ_VERBOSE set, says what became of an input (for curating the corpus).
inline void fuzz_note(const std::string& what) {
  static const bool verbose = std::getenv("HARNESS_FUZZ_VERBOSE") != nullptr;
  if (verbose) std::fprintf(stderr, "  -> %s\n", what.c_str());
}

#define FUZZ_CHECK(cond)                                                              \
  do {                                                                                \
    if (!(cond)) {                                                                    \
      std::fprintf(stderr, "%s:%d: fuzz invariant failed: %s\n", __FILE__, __LINE__, \
                   #cond);                                                            \
      std::abort();                                                                   \
    }                                                                                 \
  } while (0)
