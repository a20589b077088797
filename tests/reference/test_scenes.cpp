// Scene-level checks of the voxel model on the bundled scenes, measured by CGAL.
#include "scene_runner.hpp"

#include <catch2/catch.hpp>

using namespace harness;
using namespace harness::testing;

namespace {
// The bundled scene's effects without "contact".
std::string effects_without_contact(const std::string& name) {
  const Scene s = load_scene(bundled(name));
  std::string list = "[";
  for (const auto& [bit, n] : effect_names())
    if (s.has(bit) && bit != kContact) list += std::string(list.size() > 1 ? "," : "") + "\"" + n + "\"";
  return list + "]";
}
}  // namespace

TEST_CASE("contact lowers the final true penetration by at least 90% (cylinder_press, implant_expansion)",
          "[scenes][contact]") {
  for (const char* name : {"cylinder_press", "implant_expansion"}) {
    const SceneRun with = run_scene_measured(name, {}, 100);
    const SceneRun without = run_scene_measured(name, {{"effects", effects_without_contact(name)}}, 100);
    INFO(name << ": truly penetrating nodes at the end with contact " << with.true_pen_final << ", without "
              << without.true_pen_final << "; max depth " << with.max_depth_final << " m vs "
              << without.max_depth_final << " m");
    REQUIRE(with.finite);
    REQUIRE(without.finite);
    REQUIRE(without.true_pen_final > 50);  // the scene really does interpenetrate without contact
    CHECK(with.true_pen_final <= 0.1 * without.true_pen_final);
    WARN(name << ": true penetration at the end, contact " << with.true_pen_final << " vs none "
              << without.true_pen_final);
  }
}

TEST_CASE("both eliminators keep the bundled scenes finite", "[scenes][contact]") {
  for (const char* name : {"sphere_collision", "cylinder_press", "implant_expansion"})
    for (const char* elim : {"\"line\"", "\"plane\""}) {
      const SceneRun r = run_scene_measured(name, {{"contacts.0.eliminator", elim}, {"time.steps", "400"}}, 100);
      INFO(name << " " << elim << ": " << r.failure);
      CHECK(r.finite);
      CHECK(r.contacts_total > 0);
    }
}
