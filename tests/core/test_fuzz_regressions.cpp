// Regressions for bugs found while fuzzing the scene loader and the surface readers
// (tests/fuzz/, scripts/fuzz.sh). The inputs that found them are also in the fuzz corpus,
// tests/fuzz/corpus/, replayed by the ctest tests fuzz:replay_*.
#include "core/mesh.hpp"
#include "core/scene/scene.hpp"

#include <catch2/catch.hpp>

#include <string>

using namespace harness;

namespace {
const char* kSphere = R"({"time": {"dt": 1e-4, "steps": 1},
  "bodies": [{"name": "s", "shape": {"type": "sphere", "radius": 1, "subdivisions": 0}}]})";

std::string error_of(const std::string& text,
                     const std::vector<std::pair<std::string, std::string>>& sets = {}) {
  try {
    parse_scene(text, "scene.json", sets);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST_CASE("integers above the range of long long are rejected, not wrapped", "[scene][fuzz]") {
  // 2^64 - 1 was read as -1: a seed silently became -1, steps reported "value -1".
  std::string text = kSphere;
  text.insert(1, R"("seed": 18446744073709551615, )");
  CHECK(error_of(text) ==
        "scene.json: seed: integer 18446744073709551615 out of range (above 9223372036854775807)");
  CHECK(error_of(kSphere, {{"time.steps", "9223372036854775808"}}) ==
        "scene.json: time.steps: integer 9223372036854775808 out of range (above "
        "9223372036854775807)");
  // The largest long long itself is still an integer (and out of the range of steps).
  CHECK(error_of(kSphere, {{"time.steps", "9223372036854775807"}}) ==
        "scene.json: time.steps: value 9223372036854775807 out of range (0 to 2000000000)");
  CHECK(error_of(kSphere, {{"seed", "9223372036854775807"}}).empty());
}

TEST_CASE("a deeply nested --set value does not exhaust the stack", "[scene][fuzz]") {
  // apply_override copied the parsed value; the copy recurses once per nesting level.
  const int depth = 200000;
  const std::string deep = std::string(depth, '[') + std::string(depth, ']');
  CHECK(error_of(kSphere, {{"name", deep}}) == "scene.json: name: expected a string, got a list");
}

TEST_CASE("a --set value whose number overflows is bad input", "[scene][fuzz]") {
  // nlohmann throws out_of_range (not parse_error) for "1e999": it escaped apply_override and
  // `harness run --set time.dt=1e999` exited 1 with a raw library message instead of 2.
  // Found by fuzz_scene: "#set time.inxegdt=2e-5 ... #set bodies.0.iv: ...=21e308e-5 ...".
  CHECK(error_of(kSphere, {{"time.dt", "21e308e-5"}}) ==
        "--set time.dt: malformed JSON: number overflow in the value (21e308e-5)");
  CHECK(error_of(kSphere, {{"time.dt", "-1e999"}}) ==
        "--set time.dt: malformed JSON: number overflow in the value (-1e999)");
}
