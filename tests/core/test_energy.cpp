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

// The springs' energy is evaluated only when read (energy_audit.hpp): at the step's force point,
// reconstructed as x - dx. Read every step or now and then, the ledger is the same, it is the
// energy of the state the step started from, and the state's bits do not depend on the reading.
TEST_CASE("energy audit: the springs' energy read now and then equals the one read every step", "[energy]") {
  Simulation probe(parse_scene(lattice(R"("springs")", 1e-4), "e.json"));
  const double dt = 0.3 * probe.critical_dt();
  const std::string text = lattice(R"("springs","damping","gravity","pins","loads")", dt,
                                   R"(,"pins":[{"side":"-z"}],"loads":[{"select":{"side":"+x"},"force":[0.02,0,0],"ramp_steps":500}])");
  Simulation every(parse_scene(text, "e.json")), sometimes(parse_scene(text, "e.json"));
  double worst_u = 0.0, worst_balance_diff = 0.0;
  int compared = 0;
  for (int s = 1; s <= 1500; ++s) {
    const Points x_before = sometimes.world().x;
    every.step();
    sometimes.step();
    const EnergyLedger& a = every.energy();
    REQUIRE(a.kinetic == sometimes.energy_booked().kinetic);
    REQUIRE(a.work_external == sometimes.energy_booked().work_external);
    REQUIRE(a.dissipated == sometimes.energy_booked().dissipated);
    if (s % 37 != 0) {
      REQUIRE(sometimes.energy_current() == (s == 1));  // E*_0: the first step evaluates it in its pass
      continue;
    }
    const EnergyLedger& b = sometimes.energy();
    REQUIRE(sometimes.energy_current());
    // The energy of the state the step started from, evaluated directly.
    Points x_after = x_before;
    sometimes.world().x.swap(x_after);
    const double direct = sometimes.elastic_energy();
    sometimes.world().x.swap(x_after);
    worst_u = std::max(worst_u, std::fabs(b.elastic - direct) / std::max(direct, 1e-300));
    worst_balance_diff = std::max(worst_balance_diff, std::fabs(a.balance_error() - b.balance_error()));
    CHECK(std::fabs(a.elastic - b.elastic) <= 1e-12 * std::max(a.elastic, 1e-300));
    ++compared;
  }
  INFO("largest relative difference from the direct evaluation " << worst_u << ", of the balance " << worst_balance_diff);
  CHECK(compared == 1500 / 37);
  CHECK(worst_u < 1e-12);
  CHECK(worst_balance_diff < 1e-12);
  CHECK(every.world().x == sometimes.world().x);
  CHECK(every.energy().elastic > 0.0);
}
