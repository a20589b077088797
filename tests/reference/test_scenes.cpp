// Scene-level checks on the bundled scenes, measured by CGAL: they settle, their energy audits
// close, contact removes the penetration, and the paper's voxel model runs in every
// configuration of eliminator and force rule.
#include "scene_runner.hpp"

#include <catch2/catch.hpp>

#include <cmath>

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
const char* const kScenes[] = {"sphere_collision", "cylinder_press", "implant_expansion"};
}  // namespace

TEST_CASE("the bundled scenes settle, and their energy audits close", "[scenes][settle]") {
  for (const char* name : kScenes) {
    const SceneRun r = run_scene_measured(name, {}, 50);
    INFO(name << ": " << r.failure << " settled " << r.settled << " after " << r.steps_run << " steps, residual "
              << r.residual << ", balance error " << r.balance_error << ", contact work / energy in "
              << r.contact_injection);
    WARN(name << ": settled " << r.settled << " after " << r.steps_run << " steps, residual " << r.residual
              << ", balance error " << r.balance_error << ", contact work / energy in " << r.contact_injection);
    REQUIRE(r.finite);
    CHECK(r.settled);
    CHECK(std::fabs(r.balance_error) < 0.01);
    CHECK(r.contact_injection < 0.01);  // the default penalty is conservative
  }
}

TEST_CASE("contact lowers the final penetration depth by at least 90%", "[scenes][contact]") {
  for (const char* name : {"cylinder_press", "implant_expansion"}) {
    const SceneRun with = run_scene_measured(name, {{"time.settle", "null"}}, 100);
    const SceneRun without =
        run_scene_measured(name, {{"effects", effects_without_contact(name)}, {"time.settle", "null"}}, 100);
    INFO(name << ": truly penetrating nodes at the end with contact " << with.true_pen_final << ", without "
              << without.true_pen_final << "; max depth " << with.max_depth_final << " m vs "
              << without.max_depth_final << " m");
    REQUIRE(with.finite);
    REQUIRE(without.finite);
    REQUIRE(without.true_pen_final > 50);  // the scene really does interpenetrate without contact
    // A penalty leaves shallow penetration (depth = force / k_c): the depth, not the count, drops.
    CHECK(with.max_depth_final <= 0.1 * without.max_depth_final);
    WARN(name << ": at the end, contact " << with.true_pen_final << " nodes, depth " << with.max_depth_final
              << " m; none " << without.true_pen_final << " nodes, depth " << without.max_depth_final << " m");
  }
}

TEST_CASE("the paper's voxel model runs finite with both eliminators and every force rule", "[scenes][contact]") {
  for (const char* name : kScenes)
    for (const char* elim : {"\"line\"", "\"plane\""})
      for (const char* force : {"\"auto\"", "0.02", R"({"stiffness":500})"}) {
        // Long enough to reach contact: the spheres close a 8 mm gap at 0.1 m/s (1600 steps).
        const std::string steps = std::string(name) == "sphere_collision" ? "2000" : "400";
        const SceneRun r = run_scene_measured(name, {{"contacts.0.detector", "\"voxel\""},
                                                     {"contacts.0.eliminator", elim},
                                                     {"contacts.0.force", force},
                                                     {"time.steps", steps},
                                                     {"time.settle", "null"}},
                                              100);
        INFO(name << " " << elim << " " << force << ": " << r.failure);
        CHECK(r.finite);
        CHECK(r.contacts_total > 0);
      }
}
