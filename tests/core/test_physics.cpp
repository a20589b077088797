// Balances of the integrator and the effects: energy, momentum, pins, pressure.
#include "core/effects/gravity.hpp"
#include "core/effects/pressure.hpp"
#include "core/spring_forces.hpp"
#include "core/simulation.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <random>

using namespace harness;

namespace {
std::string box_scene(const std::string& effects, const std::string& extra_body = "", double dt = 1e-4,
                      int steps = 0) {
  return R"({"name":"t","time":{"dt":)" + std::to_string(dt) + R"(,"steps":)" + std::to_string(steps) +
         R"(},"effects":[)" + effects + R"(],
    "bodies":[{"name":"b","shape":{"type":"box","min":[0,0,0],"max":[0.03,0.03,0.03],"cells":[3,3,3]},
    "material":{"density":1000,"stiffness":50,"law":"linear"})" + extra_body + "}]}";
}
Vec3 momentum(const World& w) {
  Vec3 p = Vec3::Zero();
  for (int i = 0; i < w.num_nodes(); ++i) p += w.m[i] * w.v[i];
  return p;
}
}  // namespace

TEST_CASE("undamped linear lattice at dt = 0.5 dt_crit: energy drift <= 0.5% over 10,000 steps",
          "[physics][energy]") {
  Scene probe = parse_scene(box_scene(R"("springs")"), "energy.json");
  Simulation s0(probe);
  const double dt = 0.5 * s0.critical_dt();
  Scene sc = parse_scene(box_scene(R"("springs")", "", dt), "energy.json");
  Simulation sim(sc);
  REQUIRE(sim.stats().stability.substeps == 1);
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (Vec3& v : sim.world().v) v = 0.05 * Vec3(u(rng), u(rng), u(rng));
  // Symplectic Euler's energy oscillates about a conserved modified energy; drift is the
  // secular change, measured between the means of the first and last 500 steps.
  auto total = [&] { return sim.kinetic_energy() + sim.potential_energy(); };
  const double e0 = total();
  double first = 0.0, last = 0.0;
  for (int s = 1; s <= 10000; ++s) {
    sim.step();
    if (s <= 500) first += total();
    if (s > 9500) last += total();
  }
  first /= 500.0;
  last /= 500.0;
  INFO("E0 " << e0 << " first-window mean " << first << " last-window mean " << last);
  CHECK(std::fabs(last - first) <= 0.005 * e0);
  CHECK(std::fabs(first - e0) <= 0.05 * e0);  // the oscillation itself stays small
}

TEST_CASE("no external force: momentum conserved to 1e-10 relative", "[physics][momentum]") {
  Simulation sim(parse_scene(box_scene(R"("springs","damping")", R"(,"velocity":[0.1,-0.2,0.05])"), "p.json"));
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (Vec3& v : sim.world().v) v += 0.3 * Vec3(u(rng), u(rng), u(rng));
  const Vec3 p0 = momentum(sim.world());
  double scale = 0.0;
  for (int i = 0; i < sim.world().num_nodes(); ++i) scale += sim.world().m[i] * sim.world().v[i].norm();
  for (int s = 0; s < 2000; ++s) sim.step();
  CHECK((momentum(sim.world()) - p0).norm() <= 1e-10 * scale);
}

TEST_CASE("pinned nodes stay bit-exact", "[physics][pins]") {
  Simulation sim(parse_scene(box_scene(R"("springs","gravity","pins")", R"(,"pins":[{"side":"-z"}])"), "pin.json"));
  std::vector<int> pinned;
  for (int i = 0; i < sim.world().num_nodes(); ++i)
    if (sim.world().kinematic[i] == Kinematic::pinned) pinned.push_back(i);
  REQUIRE(pinned.size() == 16);
  Points before = sim.world().x;
  for (int s = 0; s < 500; ++s) sim.step();
  for (int i : pinned) CHECK(std::memcmp(before[i].data(), sim.world().x[i].data(), sizeof(double) * 3) == 0);
  // The rest moved under gravity.
  CHECK(sim.world().x[sim.world().num_nodes() - 1].z() < before[sim.world().num_nodes() - 1].z());
}

TEST_CASE("pins listed in the scene but not in effects stay inactive", "[physics][effects]") {
  Simulation sim(parse_scene(box_scene(R"("springs","gravity")", R"(,"pins":[{"side":"-z"}])"), "pin.json"));
  for (auto k : sim.world().kinematic) CHECK(k == Kinematic::free);
  CHECK(sim.effects_simulated() == std::vector<std::string>{"springs", "gravity"});
}

TEST_CASE("pressure: zero net force on a closed shell, inflation raises the volume", "[physics][pressure]") {
  const std::string text = R"({"name":"p","time":{"dt":2e-5,"steps":0},"effects":["springs","damping","pressure"],
    "bodies":[{"name":"s","shape":{"type":"sphere","center":[0.01,-0.02,0.3],"radius":0.02,"subdivisions":3},
    "material":{"density":1000,"stiffness":20,"damping":0.01},"pressure":{"from":0,"to":500,"ramp_steps":200}}]})";
  Simulation sim(parse_scene(text, "p.json"));
  World& w = sim.world();
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-0.001, 0.001);
  for (int i = 0; i < w.num_nodes(); ++i) w.x[i] += Vec3(u(rng), u(rng), u(rng));
  Points f(w.num_nodes(), Vec3::Zero());
  add_pressure_forces(w, 0, 1000.0, f);
  Vec3 net = Vec3::Zero();
  double mag = 0.0;
  for (const Vec3& fi : f) net += fi, mag += fi.norm();
  CHECK(net.norm() <= 1e-13 * mag);
  // Restore and inflate.
  Simulation sim2(parse_scene(text, "p.json"));
  const double v0 = enclosed_volume(sim2.world(), 0);
  for (int s = 0; s < 400; ++s) sim2.step();
  CHECK(enclosed_volume(sim2.world(), 0) > 1.01 * v0);
  CHECK(ramp_pressure(sim.scene().bodies[0].pressure, 100) == Approx(250.0));
  CHECK(ramp_pressure(sim.scene().bodies[0].pressure, 1000) == Approx(500.0));
}

TEST_CASE("drivers move their nodes kinematically inside their step window", "[physics][drivers]") {
  Simulation sim(parse_scene(box_scene(R"("springs","drivers")",
    R"(,"drivers":[{"select":{"side":"+z"},"velocity":[0,0,-0.1],"from_step":1,"to_step":10}])", 1e-4), "d.json"));
  const int top = sim.world().num_nodes() - 1;
  std::vector<int> driven = select_nodes(sim.world(), 0, sim.scene().bodies[0].drivers[0].select);
  REQUIRE(driven.size() == 16);
  const double z0 = sim.world().x[driven[0]].z();
  for (int s = 0; s < 10; ++s) sim.step();
  CHECK(sim.world().x[driven[0]].z() == Approx(z0 - 10 * 1e-4 * 0.1).epsilon(1e-12));
  sim.step();
  CHECK(sim.world().kinematic[driven[0]] == Kinematic::free);  // released after to_step
  (void)top;
}

TEST_CASE("the stability guard refuses or substeps a dt above 0.9 dt_crit", "[physics][guard]") {
  Simulation probe(parse_scene(box_scene(R"("springs")"), "g.json"));
  const double dtc = probe.critical_dt();
  CHECK_THROWS_AS(Simulation(parse_scene(box_scene(R"("springs")", "", 2.0 * dtc), "g.json")), InputError);
  std::string text = box_scene(R"("springs")", "", 2.0 * dtc);
  text.replace(text.find("\"steps\""), 7, "\"guard\":\"substep\",\"steps\"");
  Simulation sub(parse_scene(text, "g.json"));
  CHECK(sub.stats().stability.substeps == 3);
}

TEST_CASE("an inactive driver does not release nodes another driver moves", "[physics][drivers]") {
  Simulation sim(parse_scene(box_scene(R"("springs","drivers")",
    R"(,"drivers":[{"select":{"side":"+z"},"velocity":[0,0,0.1],"from_step":1,"to_step":5},
                   {"select":{"side":"+z"},"velocity":[0,0,0],"from_step":6,"to_step":-1}])", 1e-4), "d2.json"));
  std::vector<int> driven = select_nodes(sim.world(), 0, sim.scene().bodies[0].drivers[0].select);
  const double z0 = sim.world().x[driven[0]].z();
  for (int s = 0; s < 20; ++s) {
    sim.step();
    CHECK(sim.world().kinematic[driven[0]] == Kinematic::driven);
  }
  // Moved for five steps, then held.
  CHECK(sim.world().x[driven[0]].z() == Approx(z0 + 5 * 1e-4 * 0.1).epsilon(1e-12));
}

TEST_CASE("stability comes from the built effects only: no springs, no refusal and no substeps",
          "[physics][guard]") {
  Simulation probe(parse_scene(box_scene(R"("springs")"), "g.json"));
  const double dtc = probe.critical_dt();
  REQUIRE(std::isfinite(dtc));
  // A dt 20 times above the springs' limit is refused when springs are simulated ...
  CHECK_THROWS_AS(Simulation(parse_scene(box_scene(R"("springs")", "", 20.0 * dtc), "g.json")), InputError);
  // ... and taken in one step when they are not: the springs exist but are never simulated.
  for (const char* effects : {R"("gravity")", R"("damping","gravity")", ""}) {
    Simulation sim(parse_scene(box_scene(effects, "", 20.0 * dtc), "g.json"));
    CHECK(sim.stats().stability.substeps == 1);
    CHECK(std::isinf(sim.critical_dt()));
    sim.step();
    CHECK(sim.stats().stability.max_substeps == 1);
  }
}
