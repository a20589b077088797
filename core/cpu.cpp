#include "core/cpu.hpp"

#include "core/types.hpp"

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>

namespace harness {

namespace {

// HARNESS_SIMD_X86: the build compiled the avx, avx2 and avx512 kernels (CMakeLists.txt).
Isa detect() {
#if defined(HARNESS_SIMD_X86)
  __builtin_cpu_init();  // may run before libgcc's own initialisation (start-up check below)
  // libgcc reports AVX and AVX-512 only when the OS saves their registers (XCR0).
  if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") && __builtin_cpu_supports("avx2"))
    return Isa::avx512;
  if (__builtin_cpu_supports("avx2")) return Isa::avx2;
  if (__builtin_cpu_supports("avx")) return Isa::avx;
#endif
  return Isa::scalar;
}

// "scalar, avx, ..." up to best.
std::string levels_up_to(Isa best) {
  std::string s;
  for (Isa i : kAllIsas)
    if (static_cast<int>(i) <= static_cast<int>(best)) s += (s.empty() ? "" : ", ") + std::string(to_string(i));
  return s;
}

struct State {
  Isa fallback;            // HARNESS_ISA's level, else cpu_isa()
  std::atomic<int> active;
};

State& state() {
  static State s = [] {
    Isa dflt = cpu_isa();
    if (const char* env = std::getenv("HARNESS_ISA"); env && *env) {
      try {
        dflt = parse_isa(env, "HARNESS_ISA");
      } catch (const InputError& e) {
        std::fprintf(stderr, "harness: error: %s\n", e.what());
        std::exit(2);
      }
    }
    return State{dflt, {static_cast<int>(dflt)}};
  }();
  return s;
}

// HARNESS_ISA is checked when the program starts, not when a kernel first runs (which may be
// inside a parallel loop, or inside a step whose errors are reported as a failed simulation).
[[maybe_unused]] const bool checked_at_startup = (state(), true);

}  // namespace

const char* to_string(Isa isa) {
  switch (isa) {
    case Isa::scalar: return "scalar";
    case Isa::avx: return "avx";
    case Isa::avx2: return "avx2";
    case Isa::avx512: return "avx512";
  }
  return "?";
}

Isa cpu_isa() {
  static const Isa best = detect();
  return best;
}

bool isa_supported(Isa isa) { return static_cast<int>(isa) <= static_cast<int>(cpu_isa()); }

Isa parse_isa(const std::string& word, const std::string& where, Isa best) {
  for (Isa i : kAllIsas) {
    if (word != to_string(i)) continue;
    if (static_cast<int>(i) > static_cast<int>(best))
      throw InputError(where, "this processor cannot run " + word + " (it can run " + levels_up_to(best) + ")");
    return i;
  }
  throw InputError(where, "unknown instruction set '" + word + "' (expected scalar, avx, avx2 or avx512)");
}

Isa isa() { return static_cast<Isa>(state().active.load(std::memory_order_relaxed)); }

void set_isa(Isa isa) {
  if (!isa_supported(isa))
    throw std::invalid_argument(std::string("set_isa: this processor cannot run ") + to_string(isa) +
                                " (it can run " + levels_up_to(cpu_isa()) + ")");
  state().active.store(static_cast<int>(isa), std::memory_order_relaxed);
}

void reset_isa() { state().active.store(static_cast<int>(state().fallback), std::memory_order_relaxed); }

}  // namespace harness
