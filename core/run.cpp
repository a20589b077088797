#include "core/run.hpp"

#include "core/clock.hpp"
#include "core/run/columns.hpp"
#include "core/run/frames.hpp"
#include "core/run/compare.hpp"
#include "core/run/recorder.hpp"
#include "core/run/summary.hpp"
#include "core/run/surfaces.hpp"

#include <unistd.h>

#include <algorithm>
#include <chrono>
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

// The output folder: a previous run's summary is removed first, so that an interrupted run
// never looks complete; its frames are removed too, so the series is this run's only.
void prepare_output(const fs::path& dir, bool frames) {
  fs::create_directories(dir);
  fs::remove(dir / "summary.json");
  const fs::path fr = dir / "frames";
  if (fs::exists(fr))
    for (const auto& e : fs::directory_iterator(fr))
      if (e.path().extension() == ".vtk") fs::remove(e.path());
  if (frames) fs::create_directories(fr);
}

void write_frames(const fs::path& dir, const Simulation& sim, const Recorder& rec, int step) {
  const Scene& sc = sim.scene();
  if (sc.frames_every <= 0) return;
  char num[16];
  std::snprintf(num, sizeof num, "%06d", step);
  const World& w = sim.world();
  for (std::size_t b = 0; b < w.bodies.size(); ++b)
    write_vtk((dir / "frames" / (w.bodies[b].name + "_" + num + ".vtk")).string(), w, static_cast<int>(b),
              "harness " + sc.name + " body " + w.bodies[b].name + " step " + num,
              rec.penetration(static_cast<int>(b), step));
}

class ProgressLine {
 public:
  explicit ProgressLine(bool on) : on_(on && isatty(2)) {}
  void update(const Simulation& sim) {
    if (!on_) return;
    const auto now = Clock::now();
    const int s = sim.step_index(), n = sim.scene().steps;
    if (now - last_ > std::chrono::milliseconds(200) || s == n) {
      last_ = now;
      std::fprintf(stderr, "\r%s: step %d/%d (%.0f us/step)   ", sim.scene().name.c_str(), s, n, sim.last().step_us);
    }
  }
  ~ProgressLine() {
    if (on_) std::fprintf(stderr, "\n");
  }

 private:
  bool on_;
  Clock::time_point last_ = Clock::now();
};

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
    const bool last = s >= sc.steps && (!settle.present || o.settled || s >= sc.steps + settle.max_steps);
    on_step(last);
    if (last) return o;
  }
}

int run_scene(const Scene& scene, const RunOptions& opt) {
  SimulationOptions so;
  so.exact_detectors = opt.exact_detectors;
  Simulation sim(scene, so);  // may throw InputError: nothing written yet
  std::unique_ptr<Comparison> compare;
  if (!opt.compare_dir.empty()) {
    compare = std::make_unique<Comparison>(opt.compare_dir, sim);
    if (compare->converged() == std::optional<bool>(false))
      std::fprintf(stderr, "harness: warning: --compare %s: that reference did not converge (its summary.json, "
                           "reference.levels); the errors are against an unconverged state\n",
                   opt.compare_dir.c_str());
  }
  RecorderOptions ro;
  ro.measurer = opt.measurer;
  ro.compare = compare.get();
  Recorder rec(sim, ro);

  const fs::path dir(opt.out_dir);
  prepare_output(dir, scene.frames_every > 0);
  StepsWriter steps((dir / "steps.csv").string());
  write_frames(dir, sim, rec, 0);
  std::unique_ptr<TrajectoryWriter> trajectory;
  if (scene.trajectory) trajectory = std::make_unique<TrajectoryWriter>((dir / "trajectory.bin").string(), sim.world());

  RunStatus status;
  int exit_code = 0;
  {
    ProgressLine progress(opt.progress);
    const StepsOutcome o = run_steps(sim, [&](bool last) {
      rec.record(sim, last);
      if (trajectory && rec.sd_step() == sim.step_index())
        trajectory->record(surface_state(sim.world(), sim.step_index(), sim.time(), rec.signed_distance()));
      if (sim.pairs().empty()) steps.row({sim, nullptr, nullptr, nullptr, rec.kinetic_energy(), rec.potential_energy()});
      for (std::size_t p = 0; p < sim.pairs().size(); ++p)
        steps.row({sim, &sim.pairs()[p], rec.measurement(p), rec.figures(p), rec.kinetic_energy(), rec.potential_energy()});
      const int s = sim.step_index();
      if (scene.frames_every > 0 && s % scene.frames_every == 0 && !last) write_frames(dir, sim, rec, s);
      progress.update(sim);
    });
    status.settled = o.settled;
    status.settle_steps = o.settle_steps;
    if (!o.failure.empty()) {
      status.error = "step " + std::to_string(o.failed_step) + ": " + o.failure + "; last good state is step " +
                     std::to_string(o.failed_step - 1);
      std::fprintf(stderr, "harness: simulation failed: %s\n", status.error.c_str());
      status.status = "error";
      status.finite = false;
      exit_code = 3;
    }
  }
  write_frames(dir, sim, rec, sim.step_index());
  steps.close();
  if (trajectory) trajectory->close();
  write_surfaces((dir / "surfaces.csv").string(),
                 surface_state(sim.world(), sim.step_index(), sim.time(),
                               rec.sd_step() == sim.step_index() ? rec.signed_distance() : std::vector<std::vector<double>>{}));
  if (rec.references() && scene.references.cgal) write_episodes(dir.string(), sim, rec);
  nlohmann::json sum = summary_json(sim, rec, status, opt.versions);
  if (compare) add_comparison(sum, sim, rec, *compare);
  write_summary(dir.string(), sum);
  return exit_code;
}

}  // namespace harness
