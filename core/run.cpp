#include "core/run.hpp"

#include "core/clock.hpp"
#include "core/collision/responses/force_rules.hpp"
#include "core/run/columns.hpp"
#include "core/run/frames.hpp"
#include "core/run/compare.hpp"
#include "core/run/recorder.hpp"
#include "core/run/summary.hpp"
#include "core/run/surfaces.hpp"
#include "core/run/warnings.hpp"

#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <limits>
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
// A folder that cannot be made or written is bad input (exit 2), found before anything is written.
void prepare_output(const fs::path& dir, bool frames) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec || !fs::is_directory(dir)) throw InputError("--out " + dir.string(), "cannot create the output folder" + (ec ? " (" + ec.message() + ")" : std::string()));
  {
    const fs::path probe = dir / ".harness_write_test";
    std::FILE* f = std::fopen(probe.c_str(), "w");
    if (!f) throw InputError("--out " + dir.string(), "the output folder is not writable");
    std::fclose(f);
    fs::remove(probe, ec);
  }
  fs::remove(dir / "summary.json");
  const fs::path fr = dir / "frames";
  if (fs::exists(fr))
    for (const auto& e : fs::directory_iterator(fr))
      if (e.path().extension() == ".vtk" || e.path().extension() == ".vtp" || e.path().extension() == ".vtu" ||
          e.path().extension() == ".pvd")
        fs::remove(e.path());
  if (frames) fs::create_directories(fr);
}

// Contact force on each node in the last step, N (zero where none acted; NaN on the bodies of a
// pair whose response is projection, which applies no force).
Points contact_forces(const Simulation& sim) {
  const World& w = sim.world();
  Points f(static_cast<std::size_t>(w.num_nodes()), Vec3::Zero());
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (const Pair& pair : sim.pairs()) {
    if (pair.engine_contact) {  // a peer engine's position corrections: no force to report
      for (int b : {pair.spec.host, pair.spec.guest})
        for (int i = w.bodies[b].begin; i < w.bodies[b].end; ++i) f[i] = Vec3::Constant(nan);
      continue;
    }
    if (!pair.collision || !pair.collision->stepped()) continue;
    const Collision& c = *pair.collision;
    if (c.projects()) {
      for (int b : {pair.spec.host, pair.spec.guest})
        for (int i = w.bodies[b].begin; i < w.bodies[b].end; ++i) f[i] = Vec3::Constant(nan);
      continue;
    }
    scatter_pushes(f, c.pushes(), c.magnitudes());
  }
  return f;
}

std::string xml_escape(const std::string& s) {
  std::string out;
  for (char ch : s) {
    switch (ch) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += ch;
    }
  }
  return out;
}

// The frames of a run (run/frames.hpp): one file per body and frame, and with the XML formats a
// ParaView collection per body carrying each frame's physical time.
class FrameWriter {
 public:
  FrameWriter(const fs::path& dir, const Simulation& sim) : dir_(dir / "frames"), series_(sim.world().bodies.size()) {}
  void write(const Simulation& sim, const Recorder& rec, int step) {
    const Scene& sc = sim.scene();
    if (sc.frames_every <= 0) return;
    char num[16];
    std::snprintf(num, sizeof num, "%06d", step);
    const World& w = sim.world();
    const FrameFormat fmt = sc.frame_format;
    const char* ext = fmt == FrameFormat::vtp ? ".vtp" : fmt == FrameFormat::vtu ? ".vtu" : ".vtk";
    Points force;
    if (fmt != FrameFormat::vtk) force = contact_forces(sim);
    for (std::size_t b = 0; b < w.bodies.size(); ++b) {
      const Body& body = w.bodies[b];
      const int bi = static_cast<int>(b);
      const std::string file = body.name + "_" + num + ext;
      if (fmt == FrameFormat::vtk) {
        write_vtk((dir_ / file).string(), w, bi, "harness " + sc.name + " body " + body.name + " step " + num,
                  rec.penetration(bi, step));
        continue;
      }
      FrameData d;
      d.contact_force.assign(force.begin() + body.begin, force.begin() + body.begin + body.n_surface);
      if (rec.sd_step() == step && b < rec.signed_distance().size() && !rec.signed_distance()[b].empty())
        d.signed_distance = &rec.signed_distance()[b];
      d.penetrating = rec.penetration(bi, step);
      write_vtk_xml((dir_ / file).string(), w, bi, d, fmt == FrameFormat::vtu);
      auto& series = series_[b];
      if (series.empty() || series.back().second != xml_escape(file)) series.emplace_back(sim.time(), xml_escape(file));
      write_pvd((dir_ / (body.name + ".pvd")).string(), series);
    }
  }

 private:
  fs::path dir_;
  std::vector<std::vector<std::pair<double, std::string>>> series_;
};

// SIGINT and SIGTERM while a run steps: the loop stops after the current step and the run writes
// its outputs with status "interrupted" (exit 128 + signal). A second signal acts as usual.
volatile std::sig_atomic_t g_signal = 0;
extern "C" void on_stop_signal(int sig) { g_signal = sig; }

class StopSignals {
 public:
  StopSignals() {
    g_signal = 0;
    struct sigaction sa {};
    sa.sa_handler = on_stop_signal;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = SA_RESETHAND;
    sigaction(SIGINT, &sa, &old_int_);
    sigaction(SIGTERM, &sa, &old_term_);
  }
  ~StopSignals() {
    sigaction(SIGINT, &old_int_, nullptr);
    sigaction(SIGTERM, &old_term_, nullptr);
  }
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;

 private:
  struct sigaction old_int_ {}, old_term_ {};
};

// Progress on stderr: on a terminal one updating line with an ETA; otherwise (a batch log) one
// line at every tenth of the steps and every tenth of the settling budget, which logs keep.
class ProgressLine {
 public:
  explicit ProgressLine(bool on) : on_(on), tty_(on && isatty(2)) {}
  void update(const Simulation& sim) {
    if (!on_) return;
    const Scene& sc = sim.scene();
    const int s = sim.step_index(), n = sc.steps;
    const auto now = Clock::now();
    const double elapsed = std::chrono::duration<double>(now - start_).count();
    const bool settling = s > n;
    const int budget = settling ? sc.settle.max_steps : n;
    const int done = settling ? s - n : s;
    const double frac = budget > 0 ? static_cast<double>(done) / budget : 1.0;
    char what[160];
    if (settling)
      std::snprintf(what, sizeof what, "%s: settling, step %d (+%d of at most %d), residual %.3g", sc.name.c_str(), s,
                    done, budget, sim.residual());
    else
      std::snprintf(what, sizeof what, "%s: step %d/%d, ETA %.0f s", sc.name.c_str(), s, n,
                    frac > 0.0 ? elapsed * (1.0 - frac) / frac : 0.0);
    if (tty_) {
      if (now - last_ > std::chrono::milliseconds(200)) {
        last_ = now;
        std::fprintf(stderr, "\r%s (%.0f us/step)   ", what, sim.last().step_us);
      }
      return;
    }
    const int tenth = static_cast<int>(10.0 * frac + 1e-9);
    if (tenth > last_tenth_ || settling != was_settling_) {
      last_tenth_ = settling != was_settling_ ? 0 : tenth;
      was_settling_ = settling;
      std::fprintf(stderr, "harness: %s, %d %%, %.1f s\n", what, 10 * tenth, elapsed);
    }
  }
  double elapsed() const { return std::chrono::duration<double>(Clock::now() - start_).count(); }
  void finish() {
    if (tty_ && !finished_) std::fprintf(stderr, "\n");
    finished_ = true;
  }
  ~ProgressLine() { finish(); }

 private:
  bool on_, tty_;
  bool finished_ = false;
  int last_tenth_ = 0;
  bool was_settling_ = false;
  Clock::time_point start_ = Clock::now(), last_ = Clock::now();
};

// A count of a pair's summary (null when it was not measured: 0).
long long count_or_zero(const nlohmann::json& pj, const char* key) {
  return pj.contains(key) && pj[key].is_number() ? pj[key].get<long long>() : 0LL;
}

// One line at the end of a run: status, steps, settling, the stability verdict, penetration, the
// error against the reference when compared (at the end and over the final window), wall time
// and the folder.
void end_line(const Simulation& sim, const nlohmann::json& sum, const std::string& dir, double wall_s) {
  std::string pen, err;
  for (const auto& p : sum["pairs"]) {
    if (p.contains("true_pen_final") && p["true_pen_final"].is_number())
      pen += ", " + std::to_string(p["true_pen_final"].get<long long>()) + " penetrating nodes";
    const long long tun = count_or_zero(p, "tunnelled") + count_or_zero(p, "tunnelled_host");
    if (tun > 0) pen += ", " + std::to_string(tun) + " tunnelled";
    if (p.contains("error_vs_reference") && p["error_vs_reference"].is_object() &&
        p["error_vs_reference"]["pos_err_max"].is_number()) {
      const auto& e = p["error_vs_reference"];
      char b[160];
      std::snprintf(b, sizeof b, ", pos_err_max %.3g mm", 1e3 * e["pos_err_max"].get<double>());
      err += b;
      const auto& w = e["window"]["pos_err_max"];
      if (w.is_object() && w["mean"].is_number()) {
        std::snprintf(b, sizeof b, " (window mean %.3g, max %.3g, amplitude %.3g mm)", 1e3 * w["mean"].get<double>(),
                      1e3 * w["max"].get<double>(), 1e3 * w["amplitude"].get<double>());
        err += b;
      }
    }
  }
  std::string settle;
  if (sim.scene().settle.present)
    settle = sum.value("settled", false) ? ", settled" : ", not settled";
  std::string verdict;
  if (sum.contains("stability_verdict") && sum["stability_verdict"].is_string()) {
    verdict = ", " + sum["stability_verdict"].get<std::string>();
    const auto& r = sum["window"]["contact_power_ratio"];
    if (r.is_number()) {
      char b[80];
      std::snprintf(b, sizeof b, " (contact power %.3g of the input)", r.get<double>());
      verdict += b;
    }
  }
  std::fprintf(stderr, "harness: %s: %s, %d steps%s%s%s%s, %.1f s, %s\n", sim.scene().name.c_str(),
               sum.value("status", std::string("?")).c_str(), sim.step_index(), settle.c_str(), verdict.c_str(),
               pen.c_str(), err.c_str(), wall_s, dir.c_str());
}

// The warnings a finished run gives from its summary: tunnelled nodes, and contact that keeps
// injecting energy or a state that grows over the final window (run/window.hpp).
std::vector<std::string> end_warnings(const nlohmann::json& sum) {
  std::vector<std::string> out;
  for (std::size_t p = 0; p < sum["pairs"].size(); ++p) {
    const auto& pj = sum["pairs"][p];
    const long long g = count_or_zero(pj, "tunnelled"), h = count_or_zero(pj, "tunnelled_host");
    if (g > 0)
      out.push_back("contacts." + std::to_string(p) + ": " + std::to_string(g) +
                    " guest nodes tunnelled through the host (entered through one side, left through the other)");
    if (h > 0)
      out.push_back("contacts." + std::to_string(p) + ": " + std::to_string(h) +
                    " host nodes tunnelled through the guest (entered through one side, left through the other)");
  }
  const std::string v = sum.value("stability_verdict", std::string());
  const auto& w = sum["window"];
  char b[320];
  if (v == "injects" && w["kicked"] == true) {
    std::snprintf(b, sizeof b,
                  "contacts: contact injected energy that the bodies still move with over the final window (steps "
                  "%d-%d): its net work %.3g J and their mean kinetic energy %.3g J against %.3g J put in or held (limit %g of it)",
                  w["from_step"].get<int>(), w["to_step"].get<int>(), w["net_contact_work_J"].get<double>(),
                  w["kinetic_energy"]["mean"].get<double>(), w["energy_scale_J"].get<double>(), kKickShare);
    out.push_back(b);
  } else if (v == "injects") {
    std::snprintf(b, sizeof b,
                  "contacts: contact keeps injecting energy over the final window (steps %d-%d): its mean power is %.3g "
                  "of the power the scene put in (limit %g)",
                  w["from_step"].get<int>(), w["to_step"].get<int>(), w["contact_power_ratio"].get<double>(),
                  kInjectionRatio);
    out.push_back(b);
  } else if (v == "grows") {
    std::snprintf(b, sizeof b,
                  "time: the state grows over the final window (steps %d-%d): its largest kinetic energy rose %.3g times "
                  "from the first half to the second",
                  w["from_step"].get<int>(), w["to_step"].get<int>(), w["kinetic_growth"].get<double>());
    out.push_back(b);
  }
  return out;
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
    o.signal = g_signal;
    const bool last =
        o.signal != 0 || (s >= sc.steps && (!settle.present || o.settled || s >= sc.steps + settle.max_steps));
    on_step(last);
    if (last) return o;
  }
}

int run_scene(const Scene& scene, const RunOptions& opt) {
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
      rec.record(sim, last);
      if (trajectory && rec.sd_step() == sim.step_index())
        trajectory->record(surface_state(sim.world(), sim.step_index(), sim.time(), rec.signed_distance()));
      if (sim.pairs().empty()) steps.row({sim, nullptr, nullptr, nullptr, rec.kinetic_energy(), rec.potential_energy()});
      for (std::size_t p = 0; p < sim.pairs().size(); ++p)
        steps.row({sim, &sim.pairs()[p], rec.measurement(p), rec.figures(p), rec.kinetic_energy(), rec.potential_energy()});
      const int s = sim.step_index();
      if (scene.frames_every > 0 && s % scene.frames_every == 0 && !last) frames.write(sim, rec, s);
      progress.update(sim);
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
  nlohmann::json sum = summary_json(sim, rec, status, opt.versions);
  if (compare) {
    try {
      add_comparison(sum, sim, rec, *compare);
    } catch (const ComparisonError& e) {
      if (exit_code == 0) fail("--compare " + opt.compare_dir + ": " + e.what());
      sum["status"] = status.status, sum["error"] = status.error;
    }
  }
  for (const std::string& wn : end_warnings(sum)) {
    std::fprintf(stderr, "harness: warning: %s\n", wn.c_str());
    warnings.push_back(wn);
    if (opt.strict && exit_code == 0) exit_code = 2;
  }
  sum["warnings"] = warnings;
  if (opt.strict && exit_code == 2) sum["status"] = "error", sum["error"] = "--strict: " + warnings.back();
  write_summary(dir.string(), sum);
  if (opt.progress) end_line(sim, sum, dir.string(), progress.elapsed());
  return exit_code;
}

}  // namespace harness
