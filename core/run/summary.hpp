// summary.json of a run (docs/architecture.md, "Outputs"): written last, atomically, so that a
// folder without it is an interrupted run.
#pragma once

#include "core/run/recorder.hpp"
#include "core/simulation.hpp"

#include <nlohmann/json.hpp>

#include <map>
#include <string>

namespace harness {

struct RunStatus {
  std::string status = "ok";  // "ok" | "error"
  std::string error;          // empty when ok
  bool finite = true;
  bool settled = false;       // time.settle reached (meaningful with time.settle only)
  int settle_steps = 0;       // steps taken after time.steps
};

nlohmann::json summary_json(const Simulation& sim, const Recorder& rec, const RunStatus& status,
                            const std::map<std::string, std::string>& versions);
class Comparison;
// summary.json's error against the compared reference: "compare" and per pair
// "error_vs_reference" (compare.hpp).
void add_comparison(nlohmann::json& summary, const Simulation& sim, const Recorder& rec, const Comparison& cmp);
// Writes DIR/summary.json through a temporary file and a rename.
void write_summary(const std::string& dir, const nlohmann::json& summary);
// DIR/penetration_episodes.csv: one row per episode of true penetration (recorder.hpp).
void write_episodes(const std::string& dir, const Simulation& sim, const Recorder& rec);

std::string compiler_version();
std::string eigen_version();

}  // namespace harness
