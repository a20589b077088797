// The final window a run is judged on (core/run/window.hpp): its span after the forcing, its
// figures on a synthetic damped oscillation against their closed form, and the stability
// verdict of synthetic energy records (contact power as a rate, a kick, growth).
#include "core/run/window.hpp"
#include "core/scene/scene.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <complex>

using namespace harness;

namespace {

Scene scene_with(const std::string& extra_time, const std::string& bodies_extra = "") {
  const std::string text = R"({"name": "w", "time": {"dt": 0.001, "steps": 100)" + extra_time + R"(},
    "effects": ["springs", "drivers", "loads"],
    "bodies": [{"name": "b", "shape": {"type": "box", "min": [0,0,0], "max": [1,1,1], "cells": [1,1,1]},
                "material": {"stiffness": 10})" + bodies_extra + R"(}]})";
  return parse_scene(text, "test.json");
}

}  // namespace

TEST_CASE("window: the final steps after every driver, load and pressure ramp", "[window]") {
  {
    const Scene sc = scene_with("");  // nothing forces it
    CHECK(forcing_end_step(sc) == 0);
    const WindowSpan w = window_span(sc, 5000);
    CHECK(w.from == 4001);
    CHECK(w.to == 5000);
    CHECK(w.after_forcing);
  }
  {
    const Scene sc = scene_with(R"(, "window": 300)",
                                R"(, "drivers": [{"select": {"all": true}, "velocity": [0, 0, 1], "from_step": 1, "to_step": 4900},
                                                 {"select": {"all": true}, "velocity": [0, 0, 0], "from_step": 4901, "to_step": -1}],
                                     "loads": [{"select": {"all": true}, "force": [0, 0, 1], "ramp_steps": 200}])");
    CHECK(forcing_end_step(sc) == 4900);  // the hold after it is no motion
    const WindowSpan w = window_span(sc, 5000);
    CHECK(w.from == 4901);  // not 4701: the driver moved its nodes until 4900
    CHECK(w.steps() == 100);
    CHECK(w.after_forcing);
    const WindowSpan early = window_span(sc, 4000);  // a run cut before its forcing ended
    CHECK(early.from == 3701);
    CHECK_FALSE(early.after_forcing);
  }
  {
    const Scene sc = scene_with("", R"(, "drivers": [{"select": {"all": true}, "velocity": [1, 0, 0], "from_step": 1, "to_step": -1}])");
    CHECK(forcing_end_step(sc) == INT_MAX);
    CHECK_FALSE(window_span(sc, 5000).after_forcing);
  }
}

TEST_CASE("window: the figures of a sampled damped oscillation equal their closed form", "[window]") {
  // x_k = A exp(-g t_k) cos(w t_k), sampled every h with w h = pi / 2: the samples are
  // A e^{-g t_k} (1, 0, -1, 0, ...), so the window's max and min are its first positive and first
  // negative peaks and its mean is a geometric sum, Re(z^a (1 - z^n) / (1 - z)) A / n with
  // z = exp((-g + i w) h).
  const double A = 0.003, g = 2.0, h = 0.01, w = M_PI / 2 / h;
  Series s;
  for (int k = 0; k < 400; ++k) s.add(k + 1, A * std::exp(-g * k * h) * std::cos(w * k * h));
  WindowSpan span;
  span.from = 201;  // samples k = 200 .. 399 (k = 200: a positive peak, k = 202 a negative one)
  span.to = 400;
  const WindowStat st = s.over(span);
  CHECK(st.n == 200);
  CHECK(st.max == Approx(A * std::exp(-g * 200 * h)).epsilon(1e-12));
  CHECK(st.min == Approx(-A * std::exp(-g * 202 * h)).epsilon(1e-12));
  CHECK(st.amplitude() == Approx(A * (std::exp(-g * 200 * h) + std::exp(-g * 202 * h))).epsilon(1e-12));
  const std::complex<double> z = std::exp(std::complex<double>(-g * h, w * h));
  const std::complex<double> sum = std::pow(z, 200) * (1.0 - std::pow(z, 200)) / (1.0 - z);
  CHECK(st.mean == Approx(A * sum.real() / 200).epsilon(1e-9));
  // The whole run's figures are not the window's: the first peak is A.
  CHECK(s.peak() == Approx(A));
  CHECK(st.max < 0.05 * A);
}

TEST_CASE("window: contact power as a rate over the window, a kick, growth", "[window]") {
  const Scene sc = scene_with(R"(, "window": 1000)");  // dt 1 ms, nothing forces it
  const int N = 4000;
  const double e0 = 1.0;  // J put in at the start (initial energy)
  std::vector<StepEnergy> rec(N);
  SECTION("a conservative contact: no net work, a decaying oscillation: chatters") {
    for (int s = 1; s <= N; ++s) {
      const double t = s * sc.dt;
      rec[s - 1].work_contact = 0.001 * std::sin(40 * t);  // stores and returns
      rec[s - 1].kinetic = 0.1 * std::exp(-t) * std::pow(std::cos(40 * t), 2);
    }
    const StabilityJudgement j = judge_stability(sc, rec, e0, false);
    CHECK(j.verdict == "chatters");
    CHECK(j.stable());
    CHECK(j.span.from == 3001);
    CHECK(std::fabs(j.ratio) < kInjectionRatio);
    CHECK(judge_stability(sc, rec, e0, true).verdict == "settled");
  }
  SECTION("a steady injection: its rate, whatever the run's length") {
    // W_c = P t: the contact's mean power over the window is P. Nothing forces the scene: the
    // energy given at the start is taken over the window's own length (1 s), not over the 3 s
    // before it.
    const double P = 0.05;
    for (int s = 1; s <= N; ++s) rec[s - 1].work_contact = P * s * sc.dt, rec[s - 1].kinetic = 1e-3;
    const StabilityJudgement j = judge_stability(sc, rec, e0, false);
    CHECK(j.contact_power == Approx(P).epsilon(1e-9));
    CHECK(j.input_period == Approx(1.0).epsilon(1e-12));
    CHECK(j.input_power == Approx(e0 / 1.0).epsilon(1e-12));
    CHECK(j.ratio == Approx(P / e0).epsilon(1e-9));
    CHECK(j.verdict == "injects");
    // Twice as long a run: the same power and the same rho (over the time before the window it
    // would have read 7/3 as much).
    std::vector<StepEnergy> longer(2 * N);
    for (int s = 1; s <= 2 * N; ++s) longer[s - 1].work_contact = P * s * sc.dt, longer[s - 1].kinetic = 1e-3;
    const StabilityJudgement jl = judge_stability(sc, longer, e0, false);
    CHECK(jl.contact_power == Approx(P).epsilon(1e-9));
    CHECK(jl.ratio == Approx(j.ratio).epsilon(1e-12));
  }
  SECTION("a forced scene: the input power over its loading period, whatever the run's length") {
    // A driver moves the nodes for 500 steps (0.5 s) and puts in W_ext = 2 J; then the contact
    // trickles P in. rho = P / ((e0 + 2) / 0.5) at 4000 steps and at 8000.
    const Scene forced = scene_with(R"(, "window": 1000)",
                                    R"(, "drivers": [{"select": {"all": true}, "velocity": [0, 0, 1], "from_step": 1, "to_step": 500}])");
    REQUIRE(forcing_end_step(forced) == 500);
    const double P = 0.01;
    for (int n : {N, 2 * N}) {
      std::vector<StepEnergy> r(n);
      for (int s = 1; s <= n; ++s)
        r[s - 1].work_contact = P * s * forced.dt, r[s - 1].work_external = 2.0 * std::min(s, 500) / 500.0,
        r[s - 1].kinetic = 1e-3;
      const StabilityJudgement j = judge_stability(forced, r, e0, false);
      CHECK(j.input_period == Approx(0.5).epsilon(1e-12));
      CHECK(j.input_power == Approx((e0 + 2.0) / 0.5).epsilon(1e-12));
      CHECK(j.ratio == Approx(P / ((e0 + 2.0) / 0.5)).epsilon(1e-9));
    }
  }
  SECTION("a kick before the window that the bodies still move with: injects") {
    for (int s = 1; s <= N; ++s) {
      rec[s - 1].work_contact = s > 100 ? 0.5 : 0.0;  // one burst at step 100, none since
      rec[s - 1].kinetic = s > 100 ? 0.5 : 0.0;
    }
    const StabilityJudgement j = judge_stability(sc, rec, e0, false);
    CHECK(j.contact_power == 0.0);
    CHECK(j.kicked);
    CHECK(j.verdict == "injects");
    // The same burst, dissipated before the window: no longer held, not a kick.
    for (int s = 101; s <= N; ++s) rec[s - 1].kinetic = 0.5 * std::exp(-0.01 * (s - 100));
    CHECK(judge_stability(sc, rec, e0, false).verdict == "chatters");
  }
  SECTION("an oscillation that grows: grows") {
    for (int s = 1; s <= N; ++s) rec[s - 1].kinetic = 1e-3 * std::exp(0.003 * s) * std::pow(std::sin(0.3 * s), 2);
    const StabilityJudgement j = judge_stability(sc, rec, e0, false);
    CHECK(j.growth > kGrowthFactor);
    CHECK(j.verdict == "grows");
  }
}
