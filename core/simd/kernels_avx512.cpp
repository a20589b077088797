// The kernels for AVX-512, compiled with -mavx512f -mavx512vl (CMakeLists.txt; VL gives the
// four-lane kernels 32 registers). See kernels.hpp.
#if !defined(__AVX512F__) || !defined(__AVX512VL__)
#error "kernels_avx512.cpp is compiled with -mavx512f -mavx512vl"
#endif
// GCC 12's AVX-512 headers pass _mm512_undefined_*() as the pass-through operand of masked
// builtins (sqrt, min, max, casts, ...) and -Wmaybe-uninitialized flags it once inlined: a false
// positive, silenced for this file (before the headers, whose lines the warnings point at).
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#define HARNESS_SIMD_NS avx512
#include "core/simd/kernels.inl"
