// Effect "bulk" (core/effects/bulk.hpp): a box cell's resistance to a change of its volume.
// Checked against physics: forces against the energy's finite differences, the bulk energy of a
// uniform compression, no force under a rigid motion, the energy audit's balance, and a cell that
// springs alone let turn inside out and the bulk term keeps upright.
#include "core/effects/bulk.hpp"
#include "core/simulation.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <random>
#include <string>

using namespace harness;

namespace {
std::string box(const std::string& effects, double bulk, const std::string& cells = "[2,2,2]",
                const std::string& extra = "", double dt = 1e-5) {
  return R"({"name":"v","time":{"dt":)" + std::to_string(dt) + R"(,"steps":0},"effects":[)" + effects + R"(],
    "bodies":[{"name":"b","shape":{"type":"box","min":[0,0,0],"max":[0.02,0.02,0.02],"cells":)" + cells + R"(},
    "material":{"density":1000,"youngs_modulus":3000,"law":"exponential","nonlinearity":3,"bulk_modulus":)" +
         std::to_string(bulk) + "}" + extra + "}]}";
}
const BulkEffect& bulk_of(const Simulation& sim) {
  for (const auto& e : sim.effects())
    if (auto* v = dynamic_cast<const BulkEffect*>(e.get())) return *v;
  throw std::runtime_error("no bulk effect built");
}
Points forces(const BulkEffect& v, World& w) {
  std::fill(w.f.begin(), w.f.end(), Vec3::Zero());
  StepContext s;
  const_cast<BulkEffect&>(v).add_forces(w, s);
  return w.f;
}
}  // namespace

TEST_CASE("bulk: 8 corner tetrahedra per cell, a sixth of the cell each", "[bulk]") {
  Simulation sim(parse_scene(box(R"("springs","bulk")", 1e4), "v.json"));
  const BulkEffect& v = bulk_of(sim);
  REQUIRE(v.tets().size() == 8u * 8u);
  for (const BulkTet& t : v.tets()) {
    CHECK(std::abs(t.v0) == Approx(1e-6 / 6.0).epsilon(1e-12));
    CHECK(t.k == Approx(0.75e4));
  }
  CHECK(v.energy(sim.world()) == 0.0);
}

TEST_CASE("bulk: forces are minus the energy's gradient (central differences)", "[bulk]") {
  Simulation sim(parse_scene(box(R"("springs","bulk")", 1e4), "v.json"));
  World& w = sim.world();
  const BulkEffect& v = bulk_of(sim);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (Vec3& x : w.x) x += 2e-3 * Vec3(u(rng), u(rng), u(rng));  // cells of 10 mm, strained about 20 %
  const Points f = forces(v, w);
  double worst = 0.0, scale = 0.0;
  const double h = 1e-7;
  for (int i = 0; i < w.num_nodes(); ++i)
    for (int a = 0; a < 3; ++a) {
      const double x = w.x[i][a];
      w.x[i][a] = x + h;
      const double ep = v.energy(w);
      w.x[i][a] = x - h;
      const double em = v.energy(w);
      w.x[i][a] = x;
      const double fd = -(ep - em) / (2 * h);
      worst = std::max(worst, std::abs(fd - f[i][a]));
      scale = std::max(scale, std::abs(f[i][a]));
    }
  INFO("largest force " << scale << " N, largest difference " << worst << " N");
  REQUIRE(scale > 1e-3);
  CHECK(worst < 1e-6 * scale);
}

TEST_CASE("bulk: a uniform compression stores the bulk energy K V (J - 1)^2 / 2", "[bulk]") {
  const double K = 2.5e4;
  Simulation sim(parse_scene(box(R"("springs","bulk")", K), "v.json"));
  World& w = sim.world();
  const BulkEffect& v = bulk_of(sim);
  const double s = 0.9;  // every length scaled: J = s^3
  for (int i = 0; i < w.num_nodes(); ++i) w.x[i] = s * w.x0[i];
  const double J = s * s * s, V = 0.02 * 0.02 * 0.02;
  CHECK(v.energy(w) == Approx(0.5 * K * V * (J - 1) * (J - 1)).epsilon(1e-10));
  // The net force on the body is zero; inner nodes of a uniform compression feel none.
  const Points f = forces(v, w);
  Vec3 net = Vec3::Zero();
  for (const Vec3& fi : f) net += fi;
  CHECK(net.norm() < 1e-12 * K * V / 0.02);
  const int centre = [&] {
    for (int i = 0; i < w.num_nodes(); ++i)
      if ((w.x0[i] - Vec3(0.01, 0.01, 0.01)).norm() < 1e-9) return i;
    return -1;
  }();
  REQUIRE(centre >= 0);
  CHECK(f[centre].norm() < 1e-12);
}

TEST_CASE("bulk: a rigid motion stores nothing and pushes nothing", "[bulk]") {
  Simulation sim(parse_scene(box(R"("springs","bulk")", 1e4), "v.json"));
  World& w = sim.world();
  const BulkEffect& v = bulk_of(sim);
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  for (int i = 0; i < w.num_nodes(); ++i) w.x[i] = R * w.x0[i] + Vec3(0.1, -0.2, 0.3);
  CHECK(v.energy(w) < 1e-20);
  for (const Vec3& fi : forces(v, w)) CHECK(fi.norm() < 1e-9);
}

TEST_CASE("bulk: the energy audit closes with the bulk term's energy stored", "[bulk][energy]") {
  Simulation probe(parse_scene(box(R"("springs","bulk")", 3e4), "v.json"));
  const double dt = 0.5 * probe.critical_dt();
  Simulation sim(parse_scene(box(R"("springs","bulk")", 3e4, "[2,2,2]", "", dt), "v.json"));
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (Vec3& x : sim.world().v) x = 0.05 * Vec3(u(rng), u(rng), u(rng));
  sim.reset_energy();
  double worst = 0.0, stored = 0.0;
  for (int s = 0; s < 4000; ++s) {
    sim.step();
    worst = std::max(worst, std::abs(sim.energy().balance_error()));
    stored = std::max(stored, bulk_of(sim).energy(sim.world()));
  }
  INFO("largest |balance error| " << worst << ", largest bulk energy " << stored << " J");
  CHECK(stored > 1e-3 * sim.energy().kinetic + 1e-12);
  CHECK(worst < 0.005);
}

TEST_CASE("bulk: the guard's dt_crit accounts for the bulk term's stiffness", "[bulk][guard]") {
  Simulation soft(parse_scene(box(R"("springs","bulk")", 1e3), "v.json"));
  Simulation stiff(parse_scene(box(R"("springs","bulk")", 1e6), "v.json"));
  CHECK(stiff.critical_dt() < 0.5 * soft.critical_dt());
}

TEST_CASE("bulk: a cell that springs alone let turn inside out stays upright with it", "[bulk]") {
  // One cell of 20 mm on its pinned bottom face, its top face pushed down by 1 N (2.5 kPa, about the
  // Young's modulus of 3 kPa): the exponential springs' compressive force saturates (at 0.32 k l0 for
  // a = 3), they fold the cell and the top ends 34 mm below the bottom; with K = 1e5 Pa it ends
  // about 1 mm lower than it started.
  const std::string extra = R"(,"pins":[{"side":"-z"}],"loads":[{"select":{"side":"+z"},"force":[0,0,-1],"ramp_steps":2000}])";
  auto lowest_top = [&](const std::string& effects, double K) {
    Simulation probe(parse_scene(box(effects, K, "[1,1,1]", extra), "v.json"));
    const double dt = 0.3 * probe.critical_dt();
    Simulation sim(parse_scene(box(effects + R"(,"pins","loads","damping")", K, "[1,1,1]",
                                   extra + R"(,"velocity":[0,0,0])", dt),
                               "v.json"));
    for (Body& b : sim.world().bodies) b.material.mass_damping = 0.0;
    for (int s = 0; s < 6000; ++s) sim.step();
    double z = std::numeric_limits<double>::infinity();
    for (int i = 0; i < sim.world().num_nodes(); ++i)
      if (sim.world().x0[i].z() > 0.01) z = std::min(z, sim.world().x[i].z());
    return z;
  };
  const double springs = lowest_top(R"("springs")", 0.0), with_bulk = lowest_top(R"("springs","bulk")", 1e5);
  INFO("lowest top node: springs alone " << springs << " m, with the bulk term " << with_bulk << " m");
  CHECK(std::isfinite(springs));
  CHECK(springs < 0.0);
  CHECK(with_bulk > 0.015);
}

TEST_CASE("bulk: a bulk modulus on a body without cells is refused, naming the key", "[bulk][scene]") {
  const std::string text = R"({"name":"v","time":{"dt":1e-5,"steps":0},"effects":["springs","bulk"],
    "bodies":[{"name":"s","shape":{"type":"sphere","center":[0,0,0],"radius":0.01,"subdivisions":1,"fill":"volume"},)"
                           R"("material":{"bulk_modulus":1000}}]})";  // two fragments: not a valid inline scene
  try {
    parse_scene(text, "v.json");
    FAIL("accepted");
  } catch (const InputError& e) {
    const std::string what = e.what();
    INFO(what);
    CHECK(what.rfind("v.json: bodies", 0) == 0);
    CHECK(what.find("material.bulk_modulus: ") != std::string::npos);
  }
}

TEST_CASE("bulk: listed with no bulk modulus anywhere, nothing is built", "[bulk][effects]") {
  Simulation sim(parse_scene(box(R"("springs","bulk")", 0.0), "v.json"));
  for (const auto& e : sim.effects()) CHECK(std::string(e->name()) != "bulk");
}

TEST_CASE("bulk: another node order gives the same motion to rounding", "[bulk][node_order]") {
  const std::string extra = R"(,"pins":[{"side":"-z"}],"loads":[{"select":{"side":"+z"},"force":[0.3,0,-2],"ramp_steps":100}])";
  const std::string text = box(R"("springs","bulk","pins","loads")", 1e4, "[3,2,2]", extra, 2e-5);
  Simulation a(parse_scene(text, "v.json"));
  SimulationOptions o;
  o.layout.order = NodeOrder::rcm;
  Simulation b(parse_scene(text, "v.json"), o);
  for (int s = 0; s < 300; ++s) a.step(), b.step();
  double worst = 0.0;
  const Body& bb = b.world().bodies[0];
  for (int i = 0; i < bb.size(); ++i)
    worst = std::max(worst, (b.world().x[bb.begin + i] - a.world().x[bb.scene_index(i)]).norm());
  CHECK(worst < 1e-15);
}

TEST_CASE("bulk: the force pass's node energies and guard rows at a strained state", "[bulk][guard]") {
  Simulation sim(parse_scene(box(R"("springs","bulk")", 1e4), "v.json"));
  World& w = sim.world();
  const BulkEffect& v = bulk_of(sim);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (Vec3& x : w.x) x += 2e-3 * Vec3(u(rng), u(rng), u(rng));
  // The node energies the pass adds (a quarter of each tetrahedron's to each of its nodes) sum to
  // energy(); the rows it adds are the ones add_stiffness_rows gives.
  std::vector<double> node_energy(w.x.size(), 0.0);
  std::vector<Vec3> rows(w.x.size(), Vec3::Zero()), direct(w.x.size(), Vec3::Zero());
  StepContext s;
  s.spring_energy = &node_energy;
  s.guard_rows = &rows;
  std::fill(w.f.begin(), w.f.end(), Vec3::Zero());
  const_cast<BulkEffect&>(v).add_forces(w, s);
  double sum = 0.0;
  for (double e : node_energy) sum += e;
  REQUIRE(v.energy(w) > 0.0);
  CHECK(sum == Approx(v.energy(w)).epsilon(1e-12));
  REQUIRE(v.add_stiffness_rows(w, direct));
  for (std::size_t i = 0; i < rows.size(); ++i) CHECK((rows[i] - direct[i]).norm() <= 1e-12 * direct[i].norm());
  // Gershgorin: each row bounds the absolute row sum of the Hessian (central differences of the
  // forces), and not by much more than the terms' triangle inequality gives (within 3x).
  const int n = w.num_nodes();
  Eigen::MatrixXd H(3 * n, 3 * n);
  const double h = 1e-8;
  for (int j = 0; j < n; ++j)
    for (int b = 0; b < 3; ++b) {
      const double x = w.x[j][b];
      w.x[j][b] = x + h;
      const Points fp = forces(v, w);
      w.x[j][b] = x - h;
      const Points fm = forces(v, w);
      w.x[j][b] = x;
      for (int i = 0; i < n; ++i)
        for (int a = 0; a < 3; ++a) H(3 * i + a, 3 * j + b) = -(fp[i][a] - fm[i][a]) / (2 * h);
    }
  double loosest = 0.0;
  for (int i = 0; i < n; ++i)
    for (int a = 0; a < 3; ++a) {
      const double exact = H.row(3 * i + a).cwiseAbs().sum();
      CHECK(direct[i][a] >= exact * (1 - 1e-5));
      if (exact > 0) loosest = std::max(loosest, direct[i][a] / exact);
    }
  INFO("the rows exceed the Hessian's absolute row sums by at most " << loosest << "x");
  CHECK(loosest < 3.0);
}

TEST_CASE("bulk: listed without springs, the audit books its energy from the pass", "[bulk][energy]") {
  // Without springs nothing resists shear: the box deforms far, the force is strongly nonlinear and
  // the leapfrog's energy error falls fast with dt (measured 4.7 %, 1.0 %, 0.05 % at 0.5, 0.25 and
  // 0.125 dt_crit): the balance is checked at 0.125 dt_crit.
  Simulation probe(parse_scene(box(R"("bulk")", 3e4), "v.json"));
  const double dt = 0.125 * probe.critical_dt();
  Simulation sim(parse_scene(box(R"("bulk")", 3e4, "[2,2,2]", "", dt), "v.json"));
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (Vec3& x : sim.world().v) x = 0.05 * Vec3(u(rng), u(rng), u(rng));
  sim.reset_energy();
  double worst = 0.0, booked = 0.0;
  for (int s = 0; s < 2000; ++s) {
    sim.step();
    worst = std::max(worst, std::abs(sim.energy().balance_error()));
    booked = std::max(booked, sim.energy().elastic);
  }
  INFO("largest |balance error| " << worst << ", largest elastic energy booked " << booked << " J");
  CHECK(booked > 0.0);
  CHECK(worst < 0.005);
}

TEST_CASE("bulk: the implicit integrator is refused, naming the key", "[bulk][scene]") {
  const std::string text = box(R"("springs","bulk")", 1e4);
  const std::string implicit = text.substr(0, text.find("\"steps\":0")) + "\"steps\":0,\"integrator\":\"implicit_euler\"" +
                               text.substr(text.find("\"steps\":0") + 9);
  try {
    Simulation sim(parse_scene(implicit, "v.json"));
    FAIL("accepted");
  } catch (const InputError& e) {
    CHECK(std::string(e.what()).rfind("v.json: time.integrator: ", 0) == 0);
  }
}
