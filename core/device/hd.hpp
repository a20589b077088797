// HARNESS_HD marks a function that the CPU build and the CUDA backend (core/device/) compile from
// one body: __host__ __device__ under nvcc, nothing elsewhere. The CPU build never needs CUDA.
#pragma once

#if defined(__CUDACC__)
#define HARNESS_HD __host__ __device__
#else
#define HARNESS_HD
#endif
