// The final window a run is judged on (core/run/window.hpp): its span after the forcing, its
// figures on a synthetic damped oscillation against their closed form, and the stability
// verdict of synthetic energy records (contact power as a rate, a kick, growth).
#include "core/run/window.hpp"
#include "core/scene/scene.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <complex>
#include <limits>
#include <string>
#include <vector>

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

TEST_CASE("window: the class from the run alone: chatter against its length, contact input per time scale, growth above a floor", "[window]") {
  const Scene sc = scene_with(R"(, "window": 1000)");  // dt 1 ms, nothing forces it
  const int N = 4000;
  const double e0 = 1.0;  // J put in at the start (initial energy)
  std::vector<StepEnergy> rec(N);
  StabilityInputs in;
  in.chatter_length = 1e-3;  // m
  in.chatter_length_from = "voxel";
  in.time_scale = 0.01;  // s
  in.free_mass = 0.1;    // kg
  SECTION("a conservative contact, a decaying oscillation: steady below the length, chatters above it") {
    for (int s = 1; s <= N; ++s) {
      const double t = s * sc.dt;
      rec[s - 1].work_contact = 0.001 * std::sin(40 * t);  // stores and returns
      rec[s - 1].kinetic = 0.1 * std::exp(-t) * std::pow(std::cos(40 * t), 2);
      rec[s - 1].elastic = 0.5;
    }
    in.chatter_amplitude = 0.4e-3;
    const StabilityJudgement j = judge_stability(sc, rec, e0, false, in);
    CHECK(j.verdict == "steady");
    CHECK(j.stable());
    CHECK(j.span.from == 3001);
    CHECK(j.contact_input_share < kContactInputShare);
    in.chatter_amplitude = 2.5e-3;
    const StabilityJudgement jc = judge_stability(sc, rec, e0, false, in);
    CHECK(jc.verdict == "chatters");
    CHECK_FALSE(jc.stable());
    CHECK(judge_stability(sc, rec, e0, true, in).verdict == "settled");
    in.chatter_amplitude = std::numeric_limits<double>::quiet_NaN();  // not tracked: not judged on it
    CHECK(judge_stability(sc, rec, e0, false, in).verdict == "steady");
  }
  SECTION("a steady injection: per time scale against the stored energy, whatever the run's length") {
    // W_c = P t: over the window the contact puts in P T; per time scale P tau, against the stored
    // energy (elastic at the end + mean kinetic = 0.01 J): 0.01 * 0.01 / 0.01 = 0.01 (steady),
    // and with P = 0.05: 0.05 (injects; the limit is 0.02).
    for (double P : {0.01, 0.05}) {
      for (int s = 1; s <= N; ++s)
        rec[s - 1].work_contact = P * s * sc.dt, rec[s - 1].kinetic = 1e-3, rec[s - 1].elastic = 9e-3;
      in.chatter_amplitude = 0.0;
      const StabilityJudgement j = judge_stability(sc, rec, e0, false, in);
      CHECK(j.stored_energy == Approx(0.01).epsilon(1e-12));
      CHECK(j.contact_input_share == Approx(P * 0.01 / 0.01).epsilon(1e-9));
      CHECK(j.verdict == (P > kContactInputShare ? "injects" : "steady"));
      // Twice as long a run: the same share.
      std::vector<StepEnergy> longer(2 * N);
      for (int s = 1; s <= 2 * N; ++s)
        longer[s - 1].work_contact = P * s * sc.dt, longer[s - 1].kinetic = 1e-3, longer[s - 1].elastic = 9e-3;
      CHECK(judge_stability(sc, longer, e0, false, in).contact_input_share == Approx(j.contact_input_share).epsilon(1e-12));
    }
  }
  SECTION("the loading's pace does not enter: a ramp twice as slow gives the same share and class") {
    // A driver puts in W_ext = 2 J over 500 steps, or over 1000 (twice as slow); then the contact
    // trickles P in. The earlier rate (rho, recorded) halves; the class's share does not move.
    const double P = 0.05;
    std::vector<StabilityJudgement> js;
    for (int ramp : {500, 1000}) {
      const Scene forced = scene_with(R"(, "window": 1000)", R"(, "drivers": [{"select": {"all": true}, "velocity": [0, 0, 1], "from_step": 1, "to_step": )" +
                                                                std::to_string(ramp) + "}]");
      REQUIRE(forcing_end_step(forced) == ramp);
      std::vector<StepEnergy> r(N);
      for (int s = 1; s <= N; ++s)
        r[s - 1].work_contact = P * s * forced.dt, r[s - 1].work_external = 2.0 * std::min(s, ramp) / ramp,
        r[s - 1].kinetic = 1e-3, r[s - 1].elastic = 9e-3;
      in.chatter_amplitude = 0.0;
      js.push_back(judge_stability(forced, r, e0, false, in));
    }
    CHECK(js[1].ratio == Approx(js[0].ratio * 2.0).epsilon(1e-9));  // the earlier rule moved with the ramp
    CHECK(js[0].contact_input_share == Approx(js[1].contact_input_share).epsilon(1e-12));
    CHECK(js[0].verdict == js[1].verdict);
    CHECK(js[0].verdict == "injects");
  }
  SECTION("a kick before the window: judged by what the nodes do over the window, not by the work before it") {
    for (int s = 1; s <= N; ++s) {
      rec[s - 1].work_contact = s > 100 ? 0.5 : 0.0;  // one burst at step 100, none since
      rec[s - 1].kinetic = s > 100 ? 0.5 : 0.0;
      rec[s - 1].elastic = 0.0;
    }
    in.chatter_amplitude = 0.2;  // the bodies ring: their nodes move 0.2 m about their means
    const StabilityJudgement j = judge_stability(sc, rec, e0, false, in);
    CHECK(j.contact_input_share == 0.0);
    CHECK(j.verdict == "chatters");
    in.chatter_amplitude = 1e-6;  // held still
    CHECK(judge_stability(sc, rec, e0, false, in).verdict == "steady");
  }
  SECTION("an oscillation that grows: grows above the floor, not below it") {
    for (int s = 1; s <= N; ++s) {
      rec[s - 1].kinetic = 1e-3 * std::exp(0.003 * s) * std::pow(std::sin(0.3 * s), 2);
      rec[s - 1].elastic = 1.0;
    }
    in.chatter_amplitude = 0.0;
    const StabilityJudgement j = judge_stability(sc, rec, e0, false, in);
    CHECK(j.growth > kGrowthFactor);
    // floor: M (L / tau)^2 / 2 = 0.1 * (0.1)^2 / 2 = 5e-4 J, below the second half's kinetic energy
    CHECK(j.growth_floor == Approx(5e-4).epsilon(1e-12));
    CHECK(j.verdict == "grows");
    // The same growth a million times smaller: below the floor, not a growth a user sees.
    for (int s = 1; s <= N; ++s) rec[s - 1].kinetic *= 1e-6;
    CHECK(judge_stability(sc, rec, e0, false, in).verdict == "steady");
  }
}
