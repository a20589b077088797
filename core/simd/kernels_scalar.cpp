// The kernels in plain C++ (W = 1), compiled with the build's baseline flags: the scalar level,
// and the only one off x86-64. See kernels.hpp.
#define HARNESS_SIMD_NS scalar
#include "core/simd/kernels.inl"
