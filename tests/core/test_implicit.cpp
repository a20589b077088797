// Implicit Euler: stable at ten times the explicit dt_crit; without external work its energy
// does not grow; pinned nodes stay bit-exact.
#include "core/implicit.hpp"
#include "core/simulation.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <random>

using namespace harness;

namespace {
std::string lattice(double dt, const std::string& integrator, const std::string& law, const std::string& extra = "") {
  return R"({"name":"imp","time":{"dt":)" + std::to_string(dt) + R"(,"steps":0,"integrator":")" + integrator +
         R"("},"effects":["springs","pins"],
    "bodies":[{"name":"b","shape":{"type":"box","min":[0,0,0],"max":[0.04,0.02,0.02],"cells":[4,2,2]},
    "material":{"density":1000,"stiffness":2000,"law":")" + law + R"(","nonlinearity":3.0},"pins":[{"side":"-x"}])" + extra + "}]}";
}
}  // namespace

TEST_CASE("implicit Euler is stable at 10x the explicit dt_crit and its energy does not grow",
          "[implicit][stability]") {
  for (const char* law : {"linear", "exponential"}) {
    Simulation probe(parse_scene(lattice(1e-6, "symplectic_euler", law), "imp.json"));
    const double dtc = probe.stats().stability.dt_crit;
    REQUIRE(std::isfinite(dtc));
    // The explicit integrator refuses this dt ...
    CHECK_THROWS_AS(Simulation(parse_scene(lattice(10.0 * dtc, "symplectic_euler", law), "imp.json")), InputError);
    // ... the implicit one takes it.
    Simulation sim(parse_scene(lattice(10.0 * dtc, "implicit_euler", law), "imp.json"));
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (int i = 0; i < sim.world().num_nodes(); ++i)
      if (sim.world().is_free(i)) sim.world().v[i] = 0.2 * Vec3(u(rng), u(rng), u(rng));
    const Points pinned_before = sim.world().x;
    double e_prev = sim.kinetic_energy() + sim.potential_energy();
    const double e0 = e_prev;
    bool grew = false;
    for (int s = 0; s < 300; ++s) {
      sim.step();
      const double e = sim.kinetic_energy() + sim.potential_energy();
      if (e > e_prev * (1.0 + 1e-9) + 1e-15) grew = true;
      e_prev = e;
      REQUIRE(std::isfinite(e));
      CHECK(sim.stats().implicit_last.converged);
    }
    INFO(law << ": E0 " << e0 << " E_end " << e_prev);
    CHECK_FALSE(grew);
    CHECK(e_prev < e0);
    for (int i = 0; i < sim.world().num_nodes(); ++i)
      if (sim.world().kinematic[i] == Kinematic::pinned) CHECK(std::memcmp(pinned_before[i].data(), sim.world().x[i].data(), 24) == 0);
  }
}

TEST_CASE("implicit Euler agrees with symplectic Euler at small dt", "[implicit]") {
  // Gravity sag of a cantilever: both integrators, same small dt, close final positions.
  auto scene = [](const std::string& integ) {
    std::string t = lattice(2e-6, integ, "linear");
    t.replace(t.find(R"("effects":["springs","pins"])"), 28, R"("effects":["springs","pins","gravity","damping"])");
    t.replace(t.find(R"("nonlinearity":3.0)"), 18, R"("nonlinearity":3.0,"mass_damping":200)");
    return t;
  };
  Simulation a(parse_scene(scene("symplectic_euler"), "a.json")), b(parse_scene(scene("implicit_euler"), "b.json"));
  for (int s = 0; s < 3000; ++s) a.step(), b.step();
  double worst = 0.0, sag = 0.0;
  for (int i = 0; i < a.world().num_nodes(); ++i) {
    worst = std::max(worst, (a.world().x[i] - b.world().x[i]).norm());
    sag = std::max(sag, 0.0 - std::min(0.0, a.world().x[i].z()));
  }
  INFO("max position difference " << worst << " m");
  CHECK(worst < 0.05 * (0.02 + sag));  // both integrators first order: close, not equal
}

TEST_CASE("implicit Euler: a contact's stiffness in the system gives backward Euler's closed form", "[implicit][contact]") {
  // One free node (m) held by a penalty contact k along n to a pinned node: backward Euler along n
  // is (m + h^2 k) dv = h (f - h k v0.n); across n, m dv = h f. Hand computed, not a rerun.
  World w;
  w.x = {Vec3(0, 0, 0.001), Vec3(0, 0, 0)};
  w.x0 = w.x;
  w.v = {Vec3(0.1, 0.0, -0.3), Vec3::Zero()};
  w.f = {Vec3(0.2, 0.0, 1.5), Vec3::Zero()};
  w.m = {0.01, 0.01};
  w.inv_m = {100.0, 100.0};
  w.kinematic = {Kinematic::free, Kinematic::pinned};
  w.kin_v = {Vec3::Zero(), Vec3::Zero()};
  LinearSystem sys;
  sys.reset(w);
  ContactBlock cb;
  cb.node[0] = 0, cb.c[0] = 1.0, cb.node[1] = 1, cb.c[1] = -1.0, cb.count = 2;
  cb.n = Vec3(0, 0, 1);
  cb.k = 500.0;
  sys.contacts.push_back(cb);
  const double h = 1e-3, m = 0.01, k = 500.0;
  const Vec3 v0 = w.v[0], x0 = w.x[0];
  ImplicitEuler ie;
  ie.tolerance = 1e-14;
  const ImplicitStats st = ie.step(w, h, sys);
  CHECK(st.converged);
  const double dvz = h * (1.5 - h * k * v0.z()) / (m + h * h * k);
  const double dvx = h * 0.2 / m;
  CHECK(w.v[0].z() == Approx(v0.z() + dvz).epsilon(1e-12));
  CHECK(w.v[0].x() == Approx(v0.x() + dvx).epsilon(1e-12));
  CHECK(w.v[0].y() == 0.0);
  CHECK(w.x[0].z() == Approx(x0.z() + h * w.v[0].z()).epsilon(1e-12));
  CHECK(w.x[1] == Vec3::Zero());  // the pinned node stays
  // Without the contact's block the same step is the explicit force alone: a different answer.
  World w2 = w;
  w2.x[0] = x0, w2.v[0] = v0;
  LinearSystem none;
  none.reset(w2);
  ImplicitEuler ie2;
  ie2.tolerance = 1e-14;
  ie2.step(w2, h, none);
  CHECK(w2.v[0].z() == Approx(v0.z() + h * 1.5 / m).epsilon(1e-12));
  CHECK(std::fabs(w2.v[0].z() - w.v[0].z()) > 1e-3);
}

TEST_CASE("implicit Euler over a grid of steps: a linear oscillator's closed form and its first order",
          "[implicit][grid]") {
  // The real-time grid's axes on a case with a known answer: one free node held by a linear
  // stiffness k along n (the contact block: the implicit system's only stiffness), the force -k x
  // given each step. Backward Euler's step matrix is closed form: (m + h^2 k) v1 = m v0 - h k x0,
  // x1 = x0 + h v1 (per step, to rounding); its error against the exact cos(w t) at a fixed time grows
  // with the step at first order: halving h halves it (ratio -> 2), as the grid's error against its
  // step must. Hand computed, not a rerun.
  const double m = 0.01, k = 40.0, w = std::sqrt(k / m), T = 0.5;  // 3.2 periods
  auto run = [&](double h, double& x_closed) {
    World wd;
    wd.x = {Vec3(0, 0, 0.001), Vec3(0, 0, 0)};
    wd.x0 = wd.x;
    wd.v = {Vec3::Zero(), Vec3::Zero()};
    wd.f = {Vec3::Zero(), Vec3::Zero()};
    wd.m = {m, m};
    wd.inv_m = {1.0 / m, 1.0 / m};
    wd.kinematic = {Kinematic::free, Kinematic::pinned};
    wd.kin_v = {Vec3::Zero(), Vec3::Zero()};
    ImplicitEuler ie;
    ie.tolerance = 1e-14;
    double xc = 0.001, vc = 0.0;
    const int n = static_cast<int>(std::lround(T / h));
    for (int s = 0; s < n; ++s) {
      LinearSystem sys;
      sys.reset(wd);
      ContactBlock cb;
      cb.node[0] = 0, cb.c[0] = 1.0, cb.node[1] = 1, cb.c[1] = -1.0, cb.count = 2;
      cb.n = Vec3(0, 0, 1);
      cb.k = k;
      sys.contacts.push_back(cb);
      wd.f[0] = Vec3(0, 0, -k * wd.x[0].z());
      REQUIRE(ie.step(wd, h, sys).converged);
      const double v1 = (m * vc - h * k * xc) / (m + h * h * k);
      xc += h * v1, vc = v1;
      REQUIRE(wd.x[0].z() == Approx(xc).epsilon(1e-9).margin(1e-15));
    }
    x_closed = xc;
    return std::fabs(wd.x[0].z() - 0.001 * std::cos(w * n * h));
  };
  double prev = 0.0, xc = 0.0;
  for (int j = 0; j < 4; ++j) {
    const double h = 2e-4 / (1 << j);  // 0.2, 0.1, 0.05, 0.025 ms (h w 0.013 to 0.0016)
    const double err = run(h, xc);
    INFO("h " << h << " error " << err << " m");
    if (j > 0) CHECK(prev / err == Approx(2.0).epsilon(0.15));  // first order
    prev = err;
  }
}
