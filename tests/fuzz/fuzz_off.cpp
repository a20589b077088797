// libFuzzer target: the OFF reader (read_surface_text), then the shape generator.
#include "tests/fuzz/fuzz_mesh_common.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return harness_fuzz::fuzz_mesh(data, size, false);
}
