// `harness run`: simulates a scene and writes DIR/steps.csv (run/columns.hpp),
// DIR/summary.json (run/summary.hpp), DIR/frames/*.vtk (run/frames.hpp) and, with CGAL,
// DIR/penetration_episodes.csv. One loop: step, check, record (run/recorder.hpp), write.
#pragma once

#include "core/measure.hpp"
#include "core/scene.hpp"
#include "core/simulation.hpp"

#include <map>
#include <string>

namespace harness {

struct RunOptions {
  std::string out_dir = "out";
  bool progress = false;                        // a progress line on stderr
  MeasurerFactory measurer;                     // empty: references unavailable in this program
  ExactDetectorMaker exact_detectors = nullptr;  // empty: detectors "cgal", "fcl" unavailable
  std::map<std::string, std::string> versions;  // extra library versions (FCL, CGAL)
};

// Exit status: 0 done, 3 the state became non-finite (last good state and summary written).
// Throws InputError before anything is written when the scene cannot be built.
int run_scene(const Scene& scene, const RunOptions& options);

// One step with the run's checks: the state before it is kept, and when the step throws (the
// voxel region outgrew its cap) or leaves a non-finite state, it is put back and the reason is
// returned (empty: the step went through). `good_x`, `good_v` are scratch of the node count.
std::string checked_step(Simulation& sim, Points& good_x, Points& good_v);

}  // namespace harness
