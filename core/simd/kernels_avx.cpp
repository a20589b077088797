// The kernels for AVX, compiled with -mavx (CMakeLists.txt). See kernels.hpp.
#if !defined(__AVX__)
#error "kernels_avx.cpp is compiled with -mavx"
#endif
#define HARNESS_SIMD_NS avx
#include "core/simd/kernels.inl"
