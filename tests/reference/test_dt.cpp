// Results independent of dt (issue: the automatic force's separation speed was L / (2000 dt)):
// the bundled scenes at dt and at dt / 2 over the same physical time settle to the same state,
// within a tolerance set from the measurement (1.5 times it); and the old rule, a separation
// speed that doubles when dt halves, breaks that agreement where the automatic force is used.
#include "core/run/run_scene.hpp"
#include "core/run/compare.hpp"
#include "reference/reference.hpp"

#include <catch2/catch.hpp>

using namespace harness;

namespace {

// The final surfaces of a bundled scene run at dt / factor, with their signed distances.
SurfaceState settled_state(const std::string& name, int factor,
                           std::vector<std::pair<std::string, std::string>> overrides = {}) {
  overrides.emplace_back("references.solvers", "[]");
  overrides.emplace_back("output.frames_every", "0");
  const Scene sc = rescale_dt(load_scene(std::string(HARNESS_SOURCE_DIR) + "/experiments/scenes/" + name + ".json",
                                         overrides),
                              factor);
  SimulationOptions so;
  so.exact_detectors = make_exact_detector;
  Simulation sim(sc, so);
  const StepsOutcome o = run_steps(sim, [](bool) {});
  REQUIRE(o.failure.empty());
  const ContactSpec& pair = sim.pairs().at(0).spec;
  ReferenceSpec rs = reference_spec_defaults();
  rs.cgal = true;
  ReferenceMeasurer m(sim.world(), pair, rs);
  Measurement out;
  m.measure(sim.world(), pair, {}, out);
  std::vector<std::vector<double>> sd(sim.world().bodies.size());
  sd[pair.host] = *out.sd_host;
  sd[pair.guest] = *out.sd_guest;
  return surface_state(sim.world(), sim.step_index(), sim.time(), sd);
}

ReferenceErrors dt_vs_half(const std::string& name, std::vector<std::pair<std::string, std::string>> ov,
                           std::vector<std::pair<std::string, std::string>> half_ov = {}) {
  const SurfaceState a = settled_state(name, 1, ov);
  ov.insert(ov.end(), half_ov.begin(), half_ov.end());
  const SurfaceState b = settled_state(name, 2, ov);
  const Scene sc = load_scene(std::string(HARNESS_SOURCE_DIR) + "/experiments/scenes/" + name + ".json");
  int host = 0, guest = 0;
  for (std::size_t i = 0; i < sc.bodies.size(); ++i) {
    if (sc.bodies[i].name == sc.contacts[0].host) host = static_cast<int>(i);
    if (sc.bodies[i].name == sc.contacts[0].guest) guest = static_cast<int>(i);
  }
  return Comparison::errors(b, a, host, guest);
}

}  // namespace

TEST_CASE("the bundled scenes settle to the same state at dt and dt / 2", "[dt]") {
  // Measured (2026-11-23): largest position difference between the settled states, mm.
  const std::pair<const char*, double> cases[] = {
      {"sphere_collision", 2.3e-3}, {"cylinder_press", 0.154}, {"implant_expansion", 0.0527}};
  for (const auto& [name, measured_mm] : cases) {
    const ReferenceErrors e = dt_vs_half(name, {});
    WARN(name << ": dt vs dt / 2: position difference " << e.pos_err_max * 1e3 << " mm, gap " << e.gap_max * 1e3
              << " mm");
    CHECK(e.pos_err_max * 1e3 <= 1.5 * measured_mm);
  }
}

TEST_CASE("the automatic force depends on dt only through the integration, the old rule did not", "[dt]") {
  // cylinder_press with exact detection and the automatic force (its contact never settles: the
  // states after the same physical time are compared). Measured (2026-11-25, the scene settling to
  // its own tolerance, at most 4000 steps): position difference 0.033 mm and gap 0.014 mm at dt / 2;
  // the old rule (separation speed L / (2000 dt), i.e. separation_time 0.05 s at dt / 2) gives
  // 0.038 mm and 0.024 mm: its gap is 1.7 times the new rule's, beyond the margin of 1.5.
  // (Measured 2026-11-23 before the window and settle changes: 0.093 / 0.028 mm, old 0.138 / 0.068.)
  const std::vector<std::pair<std::string, std::string>> ov = {{"contacts.0.force", "\"auto\""},
                                                               {"contacts.0.two_sided", "false"},
                                                               {"time.settle.max_steps", "4000"}};
  const ReferenceErrors now = dt_vs_half("cylinder_press", ov);
  const ReferenceErrors old = dt_vs_half("cylinder_press", ov, {{"contacts.0.separation_time", "0.05"}});
  WARN("auto, dt vs dt / 2: position " << now.pos_err_max * 1e3 << " mm, gap " << now.gap_max * 1e3
                                       << " mm; old rule: position " << old.pos_err_max * 1e3 << " mm, gap "
                                       << old.gap_max * 1e3 << " mm");
  const double pos_tol = 1.5 * 0.033e-3, gap_tol = 1.5 * 0.014e-3;
  CHECK(now.pos_err_max <= pos_tol);
  CHECK(now.gap_max <= gap_tol);
  CHECK((old.pos_err_max > pos_tol || old.gap_max > gap_tol));  // the old rule fails the agreement
}
