// `harness run SCENE --device cpu|cuda`: the scene stepped by the device step (core/device/),
// timed step by step (each step waited for: the latency a real-time loop sees), with
// `--check-cpu` the CPU's Simulation stepped alike and the largest node distance between the
// two states. Writes DIR/summary.json (below) and DIR/state.csv (the final positions).
#pragma once

#include "core/run/run_scene.hpp"
#include "core/run/machine.hpp"
#include "core/scene/scene.hpp"

#include <nlohmann/json.hpp>
#include <string>

namespace harness {

struct DeviceRunOptions {
  std::string device = "cuda";
  std::string out_dir = "out";
  bool check_cpu = false;
  bool progress = true;
  ExactDetectorMaker exact_detectors = nullptr;
};

// Exit status as `harness run`: 0 done, 3 the state became non-finite (summary written).
int run_on_device(const Scene& scene, const DeviceRunOptions& o);


}  // namespace harness
