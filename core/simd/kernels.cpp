// Run-time dispatch of the SIMD kernels (kernels.hpp) on the active level (core/cpu.hpp).
#include "core/simd/kernels.hpp"

#include "core/cpu.hpp"

namespace harness::simd {

namespace scalar {
extern const Kernels table;
}
#if defined(HARNESS_SIMD_X86)  // the build compiled kernels_avx*.cpp (CMakeLists.txt)
namespace avx {
extern const Kernels table;
}
namespace avx2 {
extern const Kernels table;
}
namespace avx512 {
extern const Kernels table;
}
#endif

const Kernels& kernels(Isa isa) {
  switch (isa) {
#if defined(HARNESS_SIMD_X86)
    case Isa::avx: return avx::table;
    case Isa::avx2: return avx2::table;
    case Isa::avx512: return avx512::table;
#endif
    default: return scalar::table;
  }
}

const Kernels& kernels() { return kernels(isa()); }

}  // namespace harness::simd
