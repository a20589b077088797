#include "core/run/run_scene.hpp"

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

std::string blow_up(const World& w) {
  for (const Body& b : w.bodies) {
    Vec3 lo = Vec3::Constant(INFINITY), hi = Vec3::Constant(-INFINITY), lo0 = lo, hi0 = hi;
    for (int i = b.begin; i < b.end; ++i) {
      if (!w.x[i].allFinite() || !w.v[i].allFinite()) return "state not finite (body " + b.name + ")";
      lo = lo.cwiseMin(w.x[i]), hi = hi.cwiseMax(w.x[i]);
      lo0 = lo0.cwiseMin(w.x0[i]), hi0 = hi0.cwiseMax(w.x0[i]);
    }
    const double rest = (hi0 - lo0).maxCoeff(), now = (hi - lo).maxCoeff();
    if (b.size() > 0 && rest > 0.0 && now > kBlowUpFactor * rest) {
      char buf[160];
      std::snprintf(buf, sizeof buf, "body %s spans %.3g times its rest size", b.name.c_str(), now / rest);
      return buf;
    }
  }
  return "";
}

std::string checked_step(Simulation& sim, Points& good_x, Points& good_v) {
  World& w = sim.world();
  std::copy(w.x.begin(), w.x.end(), good_x.begin());
  std::copy(w.v.begin(), w.v.end(), good_v.begin());
  const int before = sim.step_index();
  std::string failure;
  try {
    sim.step();
  } catch (const std::runtime_error& e) {
    // The voxel region outgrew its cap during a rebuild, or the guard's substeps their cap: named
    // after the blow-up behind them, when there is one.
    failure = e.what();
    const std::string blow = blow_up(w);
    if (!blow.empty()) failure = "blow-up: " + blow + "; then: " + failure;
  }
  int bad = 0;
  if (failure.empty() && !finite_state(w, bad)) {
    std::string body;
    int node = bad;  // the body-local node in the scene's numbering (Body::scene_node)
    for (const Body& b : w.bodies)
      if (bad >= b.begin && bad < b.end) body = b.name, node = b.scene_index(bad - b.begin);
    failure = "state not finite (body " + body + ", node " + std::to_string(node) + ")";
  }
  if (!failure.empty()) sim.restore(good_x, good_v, before);
  return failure;
}

StepsOutcome run_steps(Simulation& sim, const std::function<void(bool last)>& on_step, double max_wall_s) {
  const auto t_start = Clock::now();
  const Scene& sc = sim.scene();
  const SettleSpec& settle = sc.settle;
  const int n = sim.world().num_nodes();
  Points good_x(n), good_v(n);
  StepsOutcome o;
  if (sc.steps <= 0 && !settle.present) return o;
  int below = 0;
  for (int s = 1;; ++s) {
    o.failure = checked_step(sim, good_x, good_v);
    if (o.failure.empty() && max_wall_s > 0.0 && us_since(t_start) > 1e6 * max_wall_s) {
      char buf[120];
      std::snprintf(buf, sizeof buf, "--max-wall: the run took more than %g s of wall time; stopped", max_wall_s);
      o.failure = buf;
      o.failed_step = s + 1;  // this step is kept: the failure is the next one's
      o.wall_limit = true;
      on_step(true);
      return o;
    }
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

namespace {

// --compare DIR: the reference to measure against (null without one), with a warning when that
// reference did not converge.
std::unique_ptr<Comparison> open_comparison(const std::string& dir, const char* option, const Simulation& sim) {
  if (dir.empty()) return nullptr;
  auto compare = std::make_unique<Comparison>(dir, sim, option);
  if (compare->converged() == std::optional<bool>(false))
    std::fprintf(stderr, "harness: warning: %s %s: that reference did not converge (its summary.json, "
                         "reference.levels); the errors are against an unconverged state\n",
                 option, dir.c_str());
  return compare;
}

// The warnings before the first step, printed (input errors with --strict: nothing written yet).
std::vector<std::string> take_start_warnings(const Scene& scene, const Simulation& sim, bool strict) {
  std::vector<std::string> warnings;
  for (const std::string& e : scene.edit_warnings) {  // --dt: a count rounded (the scene's times changed)
    if (strict) throw InputError("--dt", e + " (--strict)");
    std::fprintf(stderr, "harness: warning: --dt: %s\n", e.c_str());
    warnings.push_back("--dt: " + e);
  }
  for (const Warning& wn : start_warnings(sim)) {
    if (strict) throw InputError(scene.file + ": " + wn.key, wn.message + " (--strict)");
    std::fprintf(stderr, "harness: warning: %s: %s\n", wn.key.c_str(), wn.message.c_str());
    warnings.push_back(wn.key + ": " + wn.message);
  }
  return warnings;
}

// How the run ended: its status and the exit code (0; 3 a failed simulation; 128 + signal; 2
// --strict with an end warning).
struct RunEnd {
  RunStatus status;
  int exit_code = 0;
  void fail(const std::string& why) {
    std::fprintf(stderr, "harness: simulation failed: %s\n", why.c_str());
    status.error = why;
    status.status = "error";
    exit_code = 3;
  }
  // The stepping loop's outcome into the status.
  void take(const StepsOutcome& o, const Simulation& sim) {
    status.settled = o.settled;
    status.settle_steps = o.settle_steps;
    if (o.wall_limit) {
      fail("after step " + std::to_string(o.failed_step - 1) + ": " + o.failure + "; outputs hold the state after it");
    } else if (!o.failure.empty()) {
      fail("step " + std::to_string(o.failed_step) + ": " + o.failure + "; last good state is step " +
           std::to_string(o.failed_step - 1));
      status.finite = false;
    } else if (o.signal) {
      status.status = "interrupted";
      status.error = std::string(o.signal == SIGINT ? "SIGINT" : "SIGTERM") + " after step " +
                     std::to_string(sim.step_index()) + "; outputs hold the state after it";
      exit_code = 128 + o.signal;
    }
  }
};

// What a run writes as it steps: steps.csv and timing.csv, the frames, trajectory.bin.
struct RunWriters {
  StepsWriter steps;
  FrameWriter frames;
  std::unique_ptr<TrajectoryWriter> trajectory;
  RunWriters(const fs::path& dir, const Simulation& sim, const Recorder& rec)
      : steps((dir / "steps.csv").string(), (dir / "timing.csv").string()), frames(dir, sim) {
    frames.write(sim, rec, 0);
    if (sim.scene().trajectory)
      trajectory = std::make_unique<TrajectoryWriter>((dir / "trajectory.bin").string(), sim.world());
  }
  // One step's outputs (measurement and files, outside the step's time).
  void record(const Simulation& sim, Recorder& rec, bool last) {
    rec.record(sim, last);
    if (trajectory && rec.sd_step() == sim.step_index())
      trajectory->record(surface_state(sim.world(), sim.step_index(), sim.time(), rec.signed_distance()));
    if (sim.pairs().empty()) steps.row({sim, nullptr, nullptr, nullptr, rec.kinetic_energy(), rec.potential_energy()});
    for (std::size_t p = 0; p < sim.pairs().size(); ++p)
      steps.row({sim, &sim.pairs()[p], rec.measurement(p), rec.figures(p), rec.kinetic_energy(), rec.potential_energy()});
    const int s = sim.step_index();
    const int every = sim.scene().frames_every;
    if (every > 0 && s % every == 0 && !last) frames.write(sim, rec, s);
  }
  // The end: the last frame, the files closed, surfaces.csv and the penetration episodes.
  void close(const fs::path& dir, const Simulation& sim, const Recorder& rec) {
    frames.write(sim, rec, sim.step_index());
    steps.close();
    if (trajectory) trajectory->close();
    write_surfaces((dir / "surfaces.csv").string(),
                   surface_state(sim.world(), sim.step_index(), sim.time(),
                                 rec.sd_step() == sim.step_index() ? rec.signed_distance()
                                                                  : std::vector<std::vector<double>>{}));
    if (rec.references() && sim.scene().references.cgal) write_episodes(dir.string(), sim, rec);
  }
};

// summary.json and the run's outcome: the comparison with --compare, the end warnings (--strict
// makes the first one an error), written into `dir`.
RunOutcome write_run_summary(const Simulation& sim, const Recorder& rec, const RunOptions& opt, Comparison* compare,
                             Comparison* compare_also, std::vector<std::string> warnings, RunEnd& end,
                             const fs::path& dir) {
  RunOutcome out = run_outcome(sim, rec, end.status);
  nlohmann::json sum = summary_json(sim, rec, out, opt.versions);
  if (compare) {
    const std::string* which = &opt.compare_dir;
    try {
      add_comparison(sum, sim, rec, *compare, out);
      which = &opt.compare_also_dir;
      if (compare_also) add_comparison_also(sum, sim, rec, *compare_also, out.judged.span);
    } catch (const ComparisonError& e) {
      if (end.exit_code == 0)
        end.fail((which == &opt.compare_dir ? "--compare " : "--compare-also ") + *which + ": " + e.what());
      out.status = end.status;
      sum[nlohmann::json::json_pointer(summary_key::kStatus)] = end.status.status, sum["error"] = end.status.error;
    }
  }
  for (const std::string& wn : end_warnings(out)) {
    std::fprintf(stderr, "harness: warning: %s\n", wn.c_str());
    warnings.push_back(wn);
    if (opt.strict && end.exit_code == 0) end.exit_code = 2;
  }
  sum["warnings"] = warnings;
  if (opt.strict && end.exit_code == 2) {
    out.status.status = "error", out.status.error = "--strict: " + warnings.back();
    sum[nlohmann::json::json_pointer(summary_key::kStatus)] = out.status.status, sum["error"] = out.status.error;
  }
  out.warnings = warnings;
  write_summary(dir.string(), sum);
  return out;
}

}  // namespace

int run_scene(const Scene& scene, const RunOptions& opt, RunOutcome* outcome) {
  SimulationOptions so;
  so.exact_detectors = opt.exact_detectors;
  so.engine = opt.engine;
  so.layout.order = opt.node_order;
  so.jitter = opt.jitter;
  so.jitter_seed = opt.jitter_seed;
  so.responses = opt.responses;
  Simulation sim(scene, so);  // may throw InputError: nothing written yet
  if (!opt.compare_also_dir.empty() && opt.compare_dir.empty())
    throw InputError("--compare-also " + opt.compare_also_dir, "needs --compare");
  std::unique_ptr<Comparison> compare = open_comparison(opt.compare_dir, "--compare", sim);
  std::unique_ptr<Comparison> compare_also = open_comparison(opt.compare_also_dir, "--compare-also", sim);
  std::vector<std::string> warnings = take_start_warnings(scene, sim, opt.strict);
  RecorderOptions ro;
  ro.measurer = opt.measurer;
  ro.compare = compare.get();
  ro.compare_also = compare_also.get();
  Recorder rec(sim, ro);
  sim.energy_read_every(rec.energy_every());

  const fs::path dir(opt.out_dir);
  prepare_output(dir, scene.frames_every > 0);
  RunWriters writers(dir, sim, rec);
  RunEnd end;
  ProgressLine progress(opt.progress);
  try {
    const StopSignals stop_signals;
    end.take(run_steps(sim, [&](bool last) {
      const auto t_record = Clock::now();  // measurement and outputs, outside the step
      writers.record(sim, rec, last);
      progress.update(sim);
      rec.note_outside_us(us_since(t_record));
    }, opt.max_wall_s), sim);
  } catch (const ComparisonError& e) {  // a non-finite distance: never a dropped value
    end.fail("step " + std::to_string(sim.step_index()) + ": --compare " + opt.compare_dir +
             (opt.compare_also_dir.empty() ? "" : " / --compare-also " + opt.compare_also_dir) + ": " + e.what());
  }
  progress.finish();
  writers.close(dir, sim, rec);
  RunOutcome out = write_run_summary(sim, rec, opt, compare.get(), compare_also.get(), std::move(warnings), end, dir);
  if (opt.progress) print_end_line(sim, out, dir.string(), progress.elapsed());
  if (outcome) *outcome = std::move(out);
  return end.exit_code;
}

}  // namespace harness
