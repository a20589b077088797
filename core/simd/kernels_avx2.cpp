// The kernels for AVX2, compiled with -mavx2 (CMakeLists.txt). See kernels.hpp.
#if !defined(__AVX2__)
#error "kernels_avx2.cpp is compiled with -mavx2"
#endif
#define HARNESS_SIMD_NS avx2
#include "core/simd/kernels.inl"
