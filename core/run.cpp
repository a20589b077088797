#include "core/run.hpp"

#include "core/clock.hpp"

#include "core/run/columns.hpp"
#include "core/run/compare.hpp"
#include "core/run/frame_writer.hpp"
#include "core/run/output_dir.hpp"
#include "core/run/progress.hpp"
#include "core/run/recorder.hpp"
#include "core/run/signals.hpp"
#include "core/run/summary.hpp"
#include "core/run/summary_keys.hpp"
#include "core/run/surfaces.hpp"
#include "core/run/warnings.hpp"

#include <algorithm>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

namespace harness {

namespace fs = std::filesystem;

namespace {

bool finite_state(const World& w, int& bad) {
  for (bad = 0; bad < w.num_nodes(); ++bad)
    if (!w.x[bad].allFinite() || !w.v[bad].allFinite()) return false;
  return true;
}

}  // namespace

std::string checked_step(Simulation& sim, Points& good_x, Points& good_v) {
  World& w = sim.world();
  std::copy(w.x.begin(), w.x.end(), good_x.begin());
  std::copy(w.v.begin(), w.v.end(), good_v.begin());
  const int before = sim.step_index();
  std::string failure;
  try {
    sim.step();
  } catch (const std::runtime_error& e) {
    failure = e.what();  // the voxel region outgrew its cap during a rebuild
  }
  int bad = 0;
  if (failure.empty() && !finite_state(w, bad)) {
    std::string body;
    for (const Body& b : w.bodies)
      if (bad >= b.begin && bad < b.end) body = b.name;
    failure = "state not finite (body " + body + ", node " + std::to_string(bad) + ")";
  }
  if (!failure.empty()) sim.restore(good_x, good_v, before);
  return failure;
}

StepsOutcome run_steps(Simulation& sim, const std::function<void(bool last)>& on_step) {
  const Scene& sc = sim.scene();
  const SettleSpec& settle = sc.settle;
  const int n = sim.world().num_nodes();
  Points good_x(n), good_v(n);
  StepsOutcome o;
  if (sc.steps <= 0 && !settle.present) return o;
  int below = 0;
  for (int s = 1;; ++s) {
    o.failure = checked_step(sim, good_x, good_v);
    if (!o.failure.empty()) {
      o.failed_step = s;
      return o;
    }
    below = sim.residual() <= settle.tolerance ? below + 1 : 0;
    o.settle_steps = std::max(0, s - sc.steps);
    o.settled = settle.present && s >= sc.steps && below >= kSettleWindow;
    o.signal = stop_signal();
    const bool last =
        o.signal != 0 || (s >= sc.steps && (!settle.present || o.settled || s >= sc.steps + settle.max_steps));
    on_step(last);
    if (last) return o;
  }
}

int run_scene(const Scene& scene, const RunOptions& opt, RunOutcome* outcome) {
  SimulationOptions so;
  so.exact_detectors = opt.exact_detectors;
  so.engine = opt.engine;
  Simulation sim(scene, so);  // may throw InputError: nothing written yet
  std::unique_ptr<Comparison> compare;
  if (!opt.compare_dir.empty()) {
    compare = std::make_unique<Comparison>(opt.compare_dir, sim);
    if (compare->converged() == std::optional<bool>(false))
      std::fprintf(stderr, "harness: warning: --compare %s: that reference did not converge (its summary.json, "
                           "reference.levels); the errors are against an unconverged state\n",
                   opt.compare_dir.c_str());
  }
  std::vector<std::string> warnings;
  for (const Warning& wn : start_warnings(sim)) {
    if (opt.strict) throw InputError(scene.file + ": " + wn.key, wn.message + " (--strict)");
    std::fprintf(stderr, "harness: warning: %s: %s\n", wn.key.c_str(), wn.message.c_str());
    warnings.push_back(wn.key + ": " + wn.message);
  }
  RecorderOptions ro;
  ro.measurer = opt.measurer;
  ro.compare = compare.get();
  Recorder rec(sim, ro);
  sim.energy_read_every(rec.energy_every());

  const fs::path dir(opt.out_dir);
  prepare_output(dir, scene.frames_every > 0);
  StepsWriter steps((dir / "steps.csv").string());
  FrameWriter frames(dir, sim);
  frames.write(sim, rec, 0);
  std::unique_ptr<TrajectoryWriter> trajectory;
  if (scene.trajectory) trajectory = std::make_unique<TrajectoryWriter>((dir / "trajectory.bin").string(), sim.world());

  RunStatus status;
  int exit_code = 0;
  ProgressLine progress(opt.progress);
  auto fail = [&](const std::string& why) {
    std::fprintf(stderr, "harness: simulation failed: %s\n", why.c_str());
    status.error = why;
    status.status = "error";
    exit_code = 3;
  };
  try {
    const StopSignals stop_signals;
    const StepsOutcome o = run_steps(sim, [&](bool last) {
      const auto t_record = Clock::now();  // measurement and outputs, outside the step
      rec.record(sim, last);
      if (trajectory && rec.sd_step() == sim.step_index())
        trajectory->record(surface_state(sim.world(), sim.step_index(), sim.time(), rec.signed_distance()));
      if (sim.pairs().empty()) steps.row({sim, nullptr, nullptr, nullptr, rec.kinetic_energy(), rec.potential_energy()});
      for (std::size_t p = 0; p < sim.pairs().size(); ++p)
        steps.row({sim, &sim.pairs()[p], rec.measurement(p), rec.figures(p), rec.kinetic_energy(), rec.potential_energy()});
      const int s = sim.step_index();
      if (scene.frames_every > 0 && s % scene.frames_every == 0 && !last) frames.write(sim, rec, s);
      progress.update(sim);
      rec.note_outside_us(us_since(t_record));
    });
    status.settled = o.settled;
    status.settle_steps = o.settle_steps;
    if (!o.failure.empty()) {
      fail("step " + std::to_string(o.failed_step) + ": " + o.failure + "; last good state is step " +
           std::to_string(o.failed_step - 1));
      status.finite = false;
    } else if (o.signal) {
      status.status = "interrupted";
      status.error = std::string(o.signal == SIGINT ? "SIGINT" : "SIGTERM") + " after step " +
                     std::to_string(sim.step_index()) + "; outputs hold the state after it";
      exit_code = 128 + o.signal;
    }
  } catch (const ComparisonError& e) {  // a non-finite distance: never a dropped value
    fail("step " + std::to_string(sim.step_index()) + ": --compare " + opt.compare_dir + ": " + e.what());
  }
  progress.finish();
  frames.write(sim, rec, sim.step_index());
  steps.close();
  if (trajectory) trajectory->close();
  write_surfaces((dir / "surfaces.csv").string(),
                 surface_state(sim.world(), sim.step_index(), sim.time(),
                               rec.sd_step() == sim.step_index() ? rec.signed_distance() : std::vector<std::vector<double>>{}));
  if (rec.references() && scene.references.cgal) write_episodes(dir.string(), sim, rec);
  RunOutcome out = run_outcome(sim, rec, status);
  nlohmann::json sum = summary_json(sim, rec, out, opt.versions);
  if (compare) {
    try {
      add_comparison(sum, sim, rec, *compare, out);
    } catch (const ComparisonError& e) {
      if (exit_code == 0) fail("--compare " + opt.compare_dir + ": " + e.what());
      out.status = status;
      sum[nlohmann::json::json_pointer(summary_key::kStatus)] = status.status, sum["error"] = status.error;
    }
  }
  for (const std::string& wn : end_warnings(out)) {
    std::fprintf(stderr, "harness: warning: %s\n", wn.c_str());
    warnings.push_back(wn);
    if (opt.strict && exit_code == 0) exit_code = 2;
  }
  sum["warnings"] = warnings;
  if (opt.strict && exit_code == 2) {
    out.status.status = "error", out.status.error = "--strict: " + warnings.back();
    sum[nlohmann::json::json_pointer(summary_key::kStatus)] = out.status.status, sum["error"] = out.status.error;
  }
  out.warnings = warnings;
  write_summary(dir.string(), sum);
  if (opt.progress) print_end_line(sim, out, dir.string(), progress.elapsed());
  if (outcome) *outcome = std::move(out);
  return exit_code;
}

}  // namespace harness
