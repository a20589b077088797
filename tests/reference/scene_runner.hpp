// Runs a bundled scene in-process, recorded as `harness run` records it (core/run/recorder.hpp),
// with the CGAL reference measuring every `every` steps and at the last step: the figures the
// scene-level tests assert on.
#pragma once

#include "core/run/run_scene.hpp"
#include "core/run/recorder.hpp"
#include "core/scene/scene.hpp"
#include "core/simulation.hpp"
#include "reference/reference.hpp"

#include <algorithm>
#include <string>
#include <utility>
#include <vector>

namespace harness::testing {

struct SceneRun {
  bool finite = true;
  std::string failure;
  int steps_run = 0;
  double ke_peak = 0.0, ke_final = 0.0;  // J
  double max_depth_peak = 0.0;           // m, over measured steps
  double max_depth_final = 0.0;
  int true_pen_final = 0;                // guest + host, at the last step
  int tunnelled = 0;
  long long contacts_total = 0;
  double voxel = 0.0;
  // The energy audit: the largest cumulative work of contact (positive: contact injected energy)
  // over the energy the scene puts in (initial kinetic + elastic, plus external work).
  double contact_injection = 0.0;
  double balance_error = 0.0;  // at the end
  bool settled = false;        // time.settle reached (false without time.settle)
  double residual = 0.0;       // at the end
  std::string verdict;         // the stability verdict over the final window (core/run/window.hpp)
  double contact_power_ratio = 0.0;  // the earlier rule's rate (recorded, decides nothing)
  double chatter_amplitude = 0.0, chatter_length = 0.0;  // m, the class's figures (window.hpp)
  double contact_input_share = 0.0;
};

inline std::string bundled(const std::string& name) {
  return std::string(HARNESS_SOURCE_DIR) + "/experiments/scenes/" + name + ".json";
}

inline SceneRun run_scene_measured(const std::string& name,
                                   std::vector<std::pair<std::string, std::string>> overrides = {},
                                   int every = 10) {
  overrides.emplace_back("references.solvers", R"(["cgal"])");
  overrides.emplace_back("references.every", std::to_string(every));
  overrides.emplace_back("output.frames_every", "0");
  const Scene scene = load_scene(bundled(name), overrides);
  SimulationOptions so;
  so.exact_detectors = make_exact_detector;
  Simulation sim(scene, so);
  RecorderOptions ro;
  ro.measurer = make_reference_measurer;
  Recorder rec(sim, ro);
  SceneRun r;
  const StepsOutcome o = run_steps(sim, [&](bool last) {
    rec.record(sim, last);
    r.steps_run = sim.step_index();
  });
  r.failure = o.failure;
  r.finite = o.failure.empty();
  r.settled = o.settled;
  r.residual = sim.residual();
  const StabilityJudgement j = rec.judge(sim, sim.scene().settle.present && o.settled);
  r.verdict = j.verdict;
  r.contact_power_ratio = j.ratio;
  r.chatter_amplitude = j.inputs.chatter_amplitude;
  r.chatter_length = j.inputs.chatter_length;
  r.contact_input_share = j.contact_input_share;
  r.ke_peak = rec.kinetic_energy_peak();
  const EnergyLedger& e = sim.energy();
  r.contact_injection = e.work_contact_peak / std::max(1e-300, e.initial + std::max(0.0, e.work_external));
  r.balance_error = e.balance_error();
  r.ke_final = rec.kinetic_energy();
  for (std::size_t i = 0; i < sim.pairs().size(); ++i) {
    const PairTotals& t = rec.totals()[i];
    r.max_depth_peak = std::max(r.max_depth_peak, t.max_depth_peak);
    r.max_depth_final = std::max(r.max_depth_final, t.max_depth_final);
    r.true_pen_final += t.true_pen_final;
    r.contacts_total += t.contacts_total;
    r.tunnelled += rec.tunnelled(i);
    if (sim.pairs()[i].collision) r.voxel = sim.pairs()[i].collision->voxel_size();
  }
  return r;
}

}  // namespace harness::testing
