// Runs a bundled scene in-process with the CGAL reference measuring every `every` steps:
// the figures the scene-level tests assert on.
#pragma once

#include "core/run.hpp"
#include "core/scene.hpp"
#include "core/simulation.hpp"
#include "reference/reference.hpp"

#include <algorithm>
#include <cmath>
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
  int contacts_total = 0;
  double voxel = 0.0;
};

inline std::string bundled(const std::string& name) {
  return std::string(HARNESS_SOURCE_DIR) + "/experiments/scenes/" + name + ".json";
}

inline SceneRun run_scene_measured(const std::string& name,
                                   std::vector<std::pair<std::string, std::string>> overrides = {},
                                   int every = 10) {
  register_reference_detectors();
  overrides.emplace_back("references.solvers", "[]");
  overrides.emplace_back("output.frames_every", "0");
  Scene scene = load_scene(bundled(name), overrides);
  Simulation sim(scene);
  SceneRun r;
  ReferenceSpec rs;
  rs.cgal = true;
  std::vector<std::unique_ptr<Measurer>> meas;
  std::vector<Vec3> axes;
  for (const PairSlot& p : sim.pairs) {
    meas.push_back(make_reference_measurer(sim.world, p.spec, rs));
    axes.push_back(approach_axis(sim.world, p.spec));
  }
  auto measure = [&](bool final_step) {
    for (std::size_t i = 0; i < sim.pairs.size(); ++i) {
      static const std::vector<Contact> none;
      Measurement m;
      meas[i]->measure(sim.world, sim.pairs[i].spec,
                       sim.pairs[i].collision ? sim.pairs[i].collision->contacts() : none, m);
      r.max_depth_peak = std::max(r.max_depth_peak, m.max_depth);
      if (final_step) {
        r.true_pen_final += m.true_pen_guest + m.true_pen_host;
        r.max_depth_final = std::max(r.max_depth_final, m.max_depth);
      }
    }
  };
  for (int s = 1; s <= scene.steps; ++s) {
    try {
      sim.step();
    } catch (const std::runtime_error& e) {
      r.finite = false;
      r.failure = e.what();
      break;
    }
    bool ok = true;
    for (int i = 0; i < sim.world.num_nodes() && ok; ++i)
      ok = sim.world.x[i].allFinite() && sim.world.v[i].allFinite();
    if (!ok) {
      r.finite = false;
      r.failure = "state not finite at step " + std::to_string(s);
      break;
    }
    r.steps_run = s;
    const double ke = sim.kinetic_energy();
    r.ke_peak = std::max(r.ke_peak, ke);
    r.ke_final = ke;
    for (const PairSlot& p : sim.pairs) r.contacts_total += p.contacts;
    if (s % every == 0 || s == scene.steps) measure(s == scene.steps);
  }
  for (std::size_t i = 0; i < sim.pairs.size(); ++i) {
    r.tunnelled += tunnelled_nodes(sim.world, sim.pairs[i].spec, axes[i]);
    if (sim.pairs[i].collision) r.voxel = sim.pairs[i].collision->voxel_size();
  }
  return r;
}

}  // namespace harness::testing
