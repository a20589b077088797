// What a finished run found, gathered once at its end from the simulation and the recorder (the
// stability verdict over the final window, per pair the tunnelled nodes, the last true
// penetration, with --compare the errors against the reference): summary.json is written from it
// (summary.hpp), the warnings a finished run gives and its end line on stderr read it, and
// `harness reference` takes its levels' figures from it.
#pragma once

#include "core/run/compare.hpp"
#include "core/run/recorder.hpp"
#include "core/run/window.hpp"
#include "core/simulation.hpp"

#include <string>
#include <vector>

namespace harness {

struct RunStatus {
  std::string status = "ok";  // "ok" | "error" | "interrupted"
  std::string error;          // empty when ok
  bool finite = true;
  bool settled = false;       // time.settle reached (meaningful with time.settle only)
  int settle_steps = 0;       // steps taken after time.steps
};

struct PairOutcome {
  TunnelCount tunnelled;            // at the last CGAL measurement (measured false without CGAL)
  bool measured = false;            // CGAL measured at least once
  int true_pen_final = 0;           // at the last measured step (measured only)
  bool compared = false;            // errors is known (--compare)
  ReferenceErrors errors;           // the final state against the reference
  WindowStat pos_err_max_window;    // pos_err_max over the final window (--compare)
};

struct RunOutcome {
  RunStatus status;
  int steps_run = 0;
  double residual = 0.0;            // the force residual after the last step (NaN: audit off)
  StabilityStats stability;
  StabilityJudgement judged;        // over the final window
  std::string verdict;              // judged.verdict, or "failed" when the run failed
  std::vector<PairOutcome> pairs;
  std::vector<std::string> warnings;  // given at the start and at the end, in order
};

// The outcome of the run so far with status `status` (the comparison is added by add_comparison,
// summary.hpp).
RunOutcome run_outcome(const Simulation& sim, const Recorder& rec, const RunStatus& status);

// The warnings a finished run gives: tunnelled nodes, and contact that keeps injecting energy or
// a state that grows over the final window (run/window.hpp).
std::vector<std::string> end_warnings(const RunOutcome& outcome);

// One line on stderr at the end of a run: status, steps, settling, the stability verdict,
// penetration, the error against the reference when compared (at the end and over the final
// window), wall time and the folder.
void print_end_line(const Simulation& sim, const RunOutcome& outcome, const std::string& dir, double wall_s);

}  // namespace harness
