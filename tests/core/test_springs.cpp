// Spring laws: force equals the derivative of energy, by central finite differences.
#include "core/spring_forces.hpp"
#include "core/simulation.hpp"
#include "core/springs.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <vector>
#include <random>

using namespace harness;

TEST_CASE("spring tension is dE/dl for every law (central differences)", "[springs]") {
  const double L0 = 0.01;
  for (SpringLawKind kind : {SpringLawKind::linear, SpringLawKind::cubic, SpringLawKind::exponential}) {
    for (double beta : {0.0, 1e-9, 0.5, 3.0, 10.0}) {
      const SpringLaw law{kind, 80.0, beta};
      for (double strain : {-0.6, -0.2, -0.01, 0.003, 0.05, 0.3, 1.0}) {
        const double l = L0 * (1.0 + strain);
        const double h = 1e-6 * L0;
        const double fd = (spring_energy(law, L0, l + h) - spring_energy(law, L0, l - h)) / (2.0 * h);
        const double f = spring_tension(law, L0, l);
        INFO(to_string(kind) << " beta " << beta << " strain " << strain);
        CHECK(std::fabs(fd - f) <= 1e-6 * std::fabs(f) + 1e-12);
        // Tangent stiffness is df/dl.
        const double kd = (spring_tension(law, L0, l + h) - spring_tension(law, L0, l - h)) / (2.0 * h);
        CHECK(std::fabs(kd - spring_tangent(law, L0, l)) <= 1e-6 * std::fabs(kd) + 1e-9);
      }
    }
  }
}

TEST_CASE("spring_expm1: close to the library, batches equal single values", "[springs]") {
  // The halving polynomial (springs.hpp) for |x| <= 2, std::expm1 beyond: within a few units in
  // the last place of the library, also for x near 0 where expm1 matters.
  std::vector<double> x;
  for (int i = -3000; i <= 3000; ++i) x.push_back(i * 1e-3);
  for (double v : {1e-12, -1e-12, 1e-300, 0.0, -0.0, 1e-9, -3e-7, 1.9999999, -2.0, 2.0000001, 40.0, -40.0, 700.0, 710.0,
                   -800.0})
    x.push_back(v);
  const int n = static_cast<int>(x.size());
  std::vector<double> em(x.size());
  spring_expm1_batch(x.data(), em.data(), n);
  double worst = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    INFO("x = " << x[i]);
    const double a = std::expm1(x[i]);
    const double one = spring_expm1(x[i]);
    CHECK(std::memcmp(&em[i], &one, sizeof(double)) == 0);  // a batch gives the single value's bits
    if (std::isfinite(a) && a != 0.0) worst = std::max(worst, std::fabs(em[i] - a) / std::fabs(a));
    if (!std::isfinite(a) || a == 0.0) CHECK(em[i] == a);
  }
  INFO("largest relative difference from std::expm1 " << worst);
  CHECK(worst <= 2e-15);  // measured 6.5e-16 (three doublings of a 1-ulp polynomial): margin 3x
}

TEST_CASE("force per length is the tension over the length", "[springs]") {
  // The force paths use t / l in a one-division form: the same number up to a few roundings.
  const double L0 = 1.3e-3;
  for (SpringLawKind kind : {SpringLawKind::linear, SpringLawKind::cubic, SpringLawKind::exponential})
    for (double beta : {0.0, 0.5, 2.0, 10.0})
      for (double strain : {-0.9, -0.3, -1e-9, 0.0, 1e-9, 0.01, 0.4, 3.0}) {
        const SpringLaw law{kind, 100.0, beta};
        const double l = L0 * (1.0 + strain);
        const double ref = spring_tension(law, L0, l) / l;
        INFO(to_string(kind) << " beta " << beta << " strain " << strain);
        CHECK(std::fabs(spring_force_per_length(law, L0, l) - ref) <= 1e-14 * std::fabs(ref));
      }
}

TEST_CASE("spring laws match the formulas of springs.hpp", "[springs]") {
  const double L0 = 0.02, l = 0.025, k = 50.0, eps = 0.25;
  CHECK(spring_tension({SpringLawKind::linear, k, 0.0}, L0, l) == Approx(k * L0 * eps));
  CHECK(spring_tension({SpringLawKind::cubic, k, 2.0}, L0, l) == Approx(k * L0 * (eps + 2.0 * eps * eps * eps)));
  CHECK(spring_tension({SpringLawKind::exponential, k, 2.0}, L0, l) ==
        Approx(k * L0 * (std::exp(2.0 * eps) - 1.0) / 2.0));
  // Exponential tends to linear as beta -> 0; cubic with beta = 0 is linear.
  CHECK(spring_tension({SpringLawKind::exponential, k, 0.0}, L0, l) == Approx(k * L0 * eps));
  CHECK(spring_tension({SpringLawKind::cubic, k, 0.0}, L0, l) == Approx(k * L0 * eps));
  CHECK(spring_energy({SpringLawKind::exponential, k, 1e-12}, L0, l) == Approx(0.5 * k * L0 * L0 * eps * eps));
}

TEST_CASE("assembled spring forces are minus the gradient of the spring potential", "[springs]") {
  for (const char* law : {"linear", "cubic", "exponential"}) {
    const std::string text = std::string(R"({"name":"fd","time":{"dt":1e-5,"steps":0},"effects":["springs"],
      "bodies":[{"name":"b","shape":{"type":"box","min":[0,0,0],"max":[0.02,0.01,0.01],"cells":[2,1,1]},
      "material":{"stiffness":40,"law":")") + law + R"(","nonlinearity":2.0}}]})";
    Simulation sim(parse_scene(text, "fd.json"));
    World& w = sim.world();
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-0.002, 0.002);
    for (Vec3& p : w.x) p += Vec3(u(rng), u(rng), u(rng));
    Points f(w.num_nodes(), Vec3::Zero());
    add_spring_forces(w, f);
    const double h = 1e-7;
    double worst = 0.0, scale = 0.0;
    for (int i = 0; i < w.num_nodes(); ++i)
      for (int a = 0; a < 3; ++a) {
        const double x0 = w.x[i][a];
        w.x[i][a] = x0 + h;
        const double ep = spring_potential(w);
        w.x[i][a] = x0 - h;
        const double em = spring_potential(w);
        w.x[i][a] = x0;
        const double fd = -(ep - em) / (2.0 * h);
        worst = std::max(worst, std::fabs(fd - f[i][a]));
        scale = std::max(scale, std::fabs(f[i][a]));
      }
    INFO(law);
    CHECK(worst <= 1e-6 * scale);
  }
}
