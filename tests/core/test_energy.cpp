// The energy audit (core/energy.hpp): kinetic + elastic energy against the work of the external
// forces, the dissipation and the work of contact, per step.
#include "core/effects/loads.hpp"
#include "core/simulation.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <random>
#include <string>

using namespace harness;

namespace {
std::string lattice(const std::string& effects, double dt, const std::string& extra = "") {
  return R"({"name":"e","time":{"dt":)" + std::to_string(dt) + R"(,"steps":0},"effects":[)" + effects + R"(],
    "gravity":[0,0,-9.81],
    "bodies":[{"name":"b","shape":{"type":"box","min":[0,0,0],"max":[0.03,0.03,0.03],"cells":[3,3,3]},
    "material":{"density":1000,"youngs_modulus":3000,"law":"exponential","nonlinearity":3,"damping":0.001})" +
         extra + "}]}";
}
double worst_balance(Simulation& sim, int steps) {
  double worst = 0.0;
  for (int s = 0; s < steps; ++s) {
    sim.step();
    worst = std::max(worst, std::fabs(sim.energy().balance_error()));
  }
  return worst;
}
}  // namespace

TEST_CASE("energy audit: an undamped lattice keeps its energy within 0.5 %", "[energy]") {
  Simulation probe(parse_scene(lattice(R"("springs")", 1e-4), "e.json"));
  // The audit's initial energy is taken at build: restart it from the moving state.
  Simulation moving(parse_scene(lattice(R"("springs")", 0.5 * probe.critical_dt()), "e.json"));
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (Vec3& v : moving.world().v) v = 0.05 * Vec3(u(rng), u(rng), u(rng));
  moving.reset_energy();
  const double worst = worst_balance(moving, 10000);
  INFO("largest |balance error| " << worst);
  CHECK(worst < 0.005);
  CHECK(moving.energy().work_external == 0.0);
  CHECK(moving.energy().dissipated == 0.0);
}

TEST_CASE("energy audit: gravity, loads, pins and damping close the balance", "[energy]") {
  Simulation probe(parse_scene(lattice(R"("springs")", 1e-4), "e.json"));
  const double dt = 0.3 * probe.critical_dt();
  Simulation sim(parse_scene(lattice(R"("springs","damping","gravity","pins","loads")", dt,
                                     R"(,"pins":[{"side":"-z"}],"loads":[{"select":{"side":"+x"},"force":[0.02,0,0],"ramp_steps":500}])"),
                             "e.json"));
  const double worst = worst_balance(sim, 4000);
  INFO("largest |balance error| " << worst << ", W_ext " << sim.energy().work_external << ", dissipated "
                                   << sim.energy().dissipated);
  CHECK(worst < 0.01);
  CHECK(sim.energy().work_external > 0.0);
  CHECK(sim.energy().dissipated > 0.0);
}

TEST_CASE("a load's total force is shared equally among its nodes and ramped", "[energy][loads]") {
  LoadNodes l{{1, 2, 3, 4}, Vec3(0.4, 0, -0.8), 10};
  CHECK((LoadsEffect::node_force(l, 5) - Vec3(0.05, 0, -0.1)).norm() < 1e-15);
  CHECK((LoadsEffect::node_force(l, 10) - Vec3(0.1, 0, -0.2)).norm() < 1e-15);
  CHECK((LoadsEffect::node_force(l, 99) - Vec3(0.1, 0, -0.2)).norm() < 1e-15);
  l.ramp_steps = 0;
  CHECK((LoadsEffect::node_force(l, 1) - Vec3(0.1, 0, -0.2)).norm() < 1e-15);
  // In a world: the selected nodes' forces sum to the load.
  Simulation sim(parse_scene(lattice(R"("loads")", 1e-4, R"(,"loads":[{"select":{"side":"+z"},"force":[0,0.3,0]}])"),
                             "l.json"));
  sim.step();
  Vec3 total = Vec3::Zero();
  for (const Vec3& f : sim.world().f) total += f;
  CHECK((total - Vec3(0, 0.3, 0)).norm() < 1e-14);
}
