#include "core/run.hpp"

#include "core/clock.hpp"
#include "core/run/columns.hpp"
#include "core/run/frames.hpp"
#include "core/run/recorder.hpp"
#include "core/run/summary.hpp"

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

int run_scene(const Scene& scene, const RunOptions& opt) {
  SimulationOptions so;
  so.exact_detectors = opt.exact_detectors;
  Simulation sim(scene, so);  // may throw InputError: nothing written yet
  RecorderOptions ro;
  ro.measurer = opt.measurer;
  Recorder rec(sim, ro);

  const fs::path dir(opt.out_dir);
  prepare_output(dir, scene.frames_every > 0);
  StepsWriter steps((dir / "steps.csv").string());
  write_frames(dir, sim, rec, 0);

  const int n = sim.world().num_nodes();
  Points good_x(n), good_v(n);
  RunStatus status;
  int exit_code = 0;
  int below = 0;  // consecutive steps with the residual within time.settle's tolerance
  const SettleSpec& settle = scene.settle;
  {
    ProgressLine progress(opt.progress);
    for (int s = 1; s <= scene.steps || (settle.present && !status.settled && s <= scene.steps + settle.max_steps); ++s) {
      const std::string failure = checked_step(sim, good_x, good_v);
      if (!failure.empty()) {
        status.error = "step " + std::to_string(s) + ": " + failure + "; last good state is step " + std::to_string(s - 1);
        std::fprintf(stderr, "harness: simulation failed: %s\n", status.error.c_str());
        status.status = "error";
        status.finite = false;
        exit_code = 3;
        break;
      }
      rec.record(sim);
      below = sim.residual() <= settle.tolerance ? below + 1 : 0;
      if (settle.present && s >= scene.steps && below >= kSettleWindow) status.settled = true;
      status.settle_steps = std::max(0, s - scene.steps);
      if (sim.pairs().empty()) steps.row({sim, nullptr, nullptr, rec.kinetic_energy(), rec.potential_energy()});
      for (std::size_t p = 0; p < sim.pairs().size(); ++p)
        steps.row({sim, &sim.pairs()[p], rec.measurement(p), rec.kinetic_energy(), rec.potential_energy()});
      const bool last = s >= scene.steps && (!settle.present || status.settled || s >= scene.steps + settle.max_steps);
      if (scene.frames_every > 0 && s % scene.frames_every == 0 && !last) write_frames(dir, sim, rec, s);
      progress.update(sim);
    }
  }
  write_frames(dir, sim, rec, sim.step_index());
  steps.close();
  if (rec.references() && scene.references.cgal) write_episodes(dir.string(), sim, rec);
  write_summary(dir.string(), summary_json(sim, rec, status, opt.versions));
  return exit_code;
}

}  // namespace harness
