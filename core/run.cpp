#include "core/run.hpp"

#include "harness_git.hpp"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <stdexcept>

namespace harness {

namespace fs = std::filesystem;
using nlohmann::json;

const char* const kStepsColumns =
    "step,time,pair,detector,contacts,t_step_us,t_physics_us,t_detect_us,t_eliminate_us,"
    "kinetic_energy,true_pen_guest,true_pen_host,tp,fp,fn,max_depth,mean_depth,"
    "surfaces_intersect,fcl_pairs,t_cgal_us,t_fcl_us,"
    "force,fcl_max_depth,ccd_distance,t_ccd_us,penetration_volume,potential_energy,"
    "region_lo_x,region_lo_y,region_lo_z,region_hi_x,region_hi_y,region_hi_z";

std::string compiler_version() {
#if defined(__clang__)
  return std::string("clang ") + __clang_version__;
#elif defined(__GNUC__)
  return std::string("gcc ") + __VERSION__;
#else
  return "unknown";
#endif
}

std::string eigen_version() {
  return std::to_string(EIGEN_WORLD_VERSION) + "." + std::to_string(EIGEN_MAJOR_VERSION) + "." +
         std::to_string(EIGEN_MINOR_VERSION);
}

void write_vtk(const std::string& path, const World& w, int body, const std::string& title,
               const std::vector<std::uint8_t>* penetrating) {
  const Body& b = w.bodies[body];
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (!f) throw std::runtime_error("cannot write " + path);
  std::fprintf(f, "# vtk DataFile Version 3.0\n%s\nASCII\nDATASET POLYDATA\nPOINTS %d double\n",
               title.c_str(), b.n_surface);
  for (int s = 0; s < b.n_surface; ++s) {
    const Vec3& p = w.x[b.begin + s];
    std::fprintf(f, "%.9g %.9g %.9g\n", p.x(), p.y(), p.z());
  }
  std::fprintf(f, "POLYGONS %zu %zu\n", b.faces.size(), 4 * b.faces.size());
  for (const Tri& t : b.faces) std::fprintf(f, "3 %d %d %d\n", t[0], t[1], t[2]);
  if (penetrating) {
    std::fprintf(f, "POINT_DATA %d\nSCALARS penetrating int 1\nLOOKUP_TABLE default\n", b.n_surface);
    for (int v = 0; v < b.n_surface; ++v) std::fprintf(f, "%d\n", (*penetrating)[v] ? 1 : 0);
  }
  const bool ok = std::ferror(f) == 0;
  if (std::fclose(f) != 0 || !ok) throw std::runtime_error("cannot write " + path);
}

namespace {

double median(std::vector<double> v) {
  if (v.empty()) return std::nan("");
  const auto mid = v.begin() + static_cast<long>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  double m = *mid;
  if (v.size() % 2 == 0) m = 0.5 * (m + *std::max_element(v.begin(), mid));
  return m;
}

json num_or_null(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

bool finite_state(const World& w) {
  for (int i = 0; i < w.num_nodes(); ++i)
    if (!w.x[i].allFinite() || !w.v[i].allFinite()) return false;
  return true;
}

// Running totals of one pair over the run, for summary.json.
struct PairTotals {
  long long contacts_total = 0;
  long long tp = 0, fp = 0, fn = 0;
  bool measured = false;
  int true_pen_final = 0;
  double max_depth_final = 0.0, max_depth_peak = 0.0;
};

class StepsWriter {
 public:
  explicit StepsWriter(const std::string& path) : path_(path) {
    f_ = std::fopen(path.c_str(), "w");
    if (!f_) throw std::runtime_error("cannot write " + path);
    std::setvbuf(f_, nullptr, _IOFBF, 1 << 20);
    std::fprintf(f_, "%s\n", kStepsColumns);
  }
  ~StepsWriter() {
    if (f_) std::fclose(f_);
  }
  void row(const Simulation& sim, const PairSlot* p, const Measurement* m, double ke, double pe) {
    std::FILE* f = f_;
    std::fprintf(f, "%d,%.9g,", sim.step_index, sim.time);
    if (p) {
      std::fprintf(f, "%s,%s,", p->label.c_str(), p->collision ? p->spec.detector.c_str() : "none");
      if (p->collision) std::fprintf(f, "%d,", p->contacts);
      else std::fputc(',', f);
    } else {
      std::fputs(",,,", f);
    }
    std::fprintf(f, "%.3f,%.3f,", sim.last.step_us, sim.last.physics_us);
    if (p && p->collision) std::fprintf(f, "%.3f,%.3f,", p->t_detect_us, p->t_eliminate_us);
    else std::fputs(",,", f);
    std::fprintf(f, "%.9g,", ke);
    if (m && m->has_cgal)
      std::fprintf(f, "%d,%d,%d,%d,%d,%.9g,%.9g,%d,", m->true_pen_guest, m->true_pen_host, m->tp, m->fp,
                   m->fn, m->max_depth, m->mean_depth, m->surfaces_intersect ? 1 : 0);
    else
      std::fputs(",,,,,,,,", f);
    if (m && m->has_fcl) std::fprintf(f, "%d,", m->fcl_pairs);
    else std::fputc(',', f);
    if (m && m->has_cgal) std::fprintf(f, "%.3f,", m->t_cgal_us);
    else std::fputc(',', f);
    if (m && m->has_fcl) std::fprintf(f, "%.3f,", m->t_fcl_us);
    else std::fputc(',', f);
    // Extra columns.
    if (p && p->collision) std::fprintf(f, "%.9g,", p->force);
    else std::fputc(',', f);
    if (m && m->has_fcl) std::fprintf(f, "%.9g,", m->fcl_max_depth);
    else std::fputc(',', f);
    if (m && m->has_ccd) std::fprintf(f, "%.9g,%.3f,", m->ccd_distance, m->t_ccd_us);
    else std::fputs(",,", f);
    if (m && m->has_volume) std::fprintf(f, "%.9g,", m->penetration_volume);
    else std::fputc(',', f);
    std::fprintf(f, "%.9g", pe);
    Vec3 lo, hi;
    if (p && p->collision && p->collision->detector().region(lo, hi))
      std::fprintf(f, ",%.9g,%.9g,%.9g,%.9g,%.9g,%.9g\n", lo.x(), lo.y(), lo.z(), hi.x(), hi.y(), hi.z());
    else
      std::fputs(",,,,,,\n", f);
  }
  void close() {
    const bool ok = std::ferror(f_) == 0;
    const int rc = std::fclose(f_);
    f_ = nullptr;
    if (rc != 0 || !ok) throw std::runtime_error("cannot write " + path_);
  }

 private:
  std::string path_;
  std::FILE* f_ = nullptr;
};

void write_json_atomic(const fs::path& path, const json& j) {
  const fs::path tmp = path.string() + ".tmp";
  {
    std::ofstream o(tmp);
    o << j.dump(2) << "\n";
    if (!o) throw std::runtime_error("cannot write " + tmp.string());
  }
  fs::rename(tmp, path);
}

}  // namespace

Vec3 approach_axis(const World& w, const ContactSpec& pair) {
  Vec3 hl, hh, gl, gh;
  body_bounds(w, pair.host, hl, hh);
  body_bounds(w, pair.guest, gl, gh);
  Vec3 a = 0.5 * (gl + gh) - 0.5 * (hl + hh);
  const double n = a.norm();
  return n > 0.0 && std::isfinite(n) ? Vec3(a / n) : Vec3(Vec3::UnitZ());
}

int tunnelled_nodes(const World& w, const ContactSpec& pair, const Vec3& axis) {
  const Body& H = w.bodies[pair.host];
  const Body& G = w.bodies[pair.guest];
  double lo = std::numeric_limits<double>::infinity();
  for (int i = H.begin; i < H.end; ++i) lo = std::min(lo, w.x[i].dot(axis));
  int n = 0;
  for (int i = G.begin; i < G.end; ++i)
    if (w.x[i].dot(axis) < lo) ++n;
  return n;
}

int run_scene(const Scene& scene, const RunOptions& opt) {
  Simulation sim(scene);  // may throw InputError: nothing written yet
  World& w = sim.world;

  const bool want_refs = scene.references.cgal || scene.references.fcl || scene.references.ccd;
  std::vector<std::unique_ptr<Measurer>> measurers;
  if (want_refs) {
    if (!opt.measurer)
      throw InputError(scene.file + ": references.solvers", "this build has no reference solvers");
    for (const PairSlot& p : sim.pairs) measurers.push_back(opt.measurer(w, p.spec, scene.references));
  }

  // The output folder: a previous run's summary is removed first, so that an interrupted run
  // never looks complete; its frames are removed too, so the series is this run's only.
  const fs::path dir(opt.out_dir);
  fs::create_directories(dir);
  fs::remove(dir / "summary.json");
  const fs::path frames = dir / "frames";
  if (fs::exists(frames))
    for (const auto& e : fs::directory_iterator(frames))
      if (e.path().extension() == ".vtk") fs::remove(e.path());
  if (scene.frames_every > 0) fs::create_directories(frames);

  // Truly penetrating nodes per body (OR over its pairs) at the last measured step, for the
  // frames; and the penetration episodes of every node, for the persistence statistics.
  std::vector<std::vector<std::uint8_t>> pen_flags(w.bodies.size());
  for (std::size_t b = 0; b < w.bodies.size(); ++b) pen_flags[b].assign(w.bodies[b].size(), 0);
  int pen_step = -1;
  struct Episode {
    int pair, body, node, first, last;
    bool open;
  };
  std::vector<Episode> episodes;
  std::vector<std::vector<int>> open_episode(2 * sim.pairs.size());  // per pair and role: index or -1
  for (std::size_t pi = 0; pi < sim.pairs.size(); ++pi) {
    open_episode[2 * pi].assign(w.bodies[sim.pairs[pi].spec.guest].size(), -1);
    open_episode[2 * pi + 1].assign(w.bodies[sim.pairs[pi].spec.host].size(), -1);
  }
  auto track = [&](std::size_t pi, int role, const std::vector<std::uint8_t>& flags, int step) {
    const int body = role == 0 ? sim.pairs[pi].spec.guest : sim.pairs[pi].spec.host;
    std::vector<int>& open = open_episode[2 * pi + role];
    for (std::size_t i = 0; i < flags.size(); ++i) {
      if (flags[i]) {
        pen_flags[body][i] = 1;
        if (open[i] < 0) {
          open[i] = static_cast<int>(episodes.size());
          episodes.push_back({static_cast<int>(pi), body, static_cast<int>(i), step, step, true});
        } else {
          episodes[open[i]].last = step;
        }
      } else if (open[i] >= 0) {
        episodes[open[i]].open = false;
        open[i] = -1;
      }
    }
  };

  auto write_frames = [&](int step) {
    if (scene.frames_every <= 0) return;
    char num[16];
    std::snprintf(num, sizeof num, "%06d", step);
    for (std::size_t b = 0; b < w.bodies.size(); ++b)
      write_vtk((frames / (w.bodies[b].name + "_" + num + ".vtk")).string(), w, static_cast<int>(b),
                "harness " + scene.name + " body " + w.bodies[b].name + " step " + num,
                pen_step == step ? &pen_flags[b] : nullptr);
  };

  // Approach axis of each pair at rest (host centre to guest centre), for the tunnelling count.
  std::vector<Vec3> axes;
  for (const PairSlot& p : sim.pairs) axes.push_back(approach_axis(w, p.spec));

  StepsWriter steps((dir / "steps.csv").string());
  write_frames(0);

  const int n = w.num_nodes();
  Points good_x(n), good_v(n);  // last good state, kept for the finiteness watch
  std::vector<PairTotals> totals(sim.pairs.size());
  std::vector<Measurement> meas(sim.pairs.size());
  std::vector<double> t_step, t_phys, t_det, t_elim, t_cgal, t_fcl;
  t_step.reserve(scene.steps);
  t_phys.reserve(scene.steps);
  t_det.reserve(scene.steps);
  t_elim.reserve(scene.steps);

  std::string status = "ok", error;
  double ke_peak = sim.kinetic_energy();
  int exit_code = 0;
  const bool tty = opt.progress && isatty(2);
  auto last_progress = std::chrono::steady_clock::now();

  for (int s = 1; s <= scene.steps; ++s) {
    std::copy(w.x.begin(), w.x.end(), good_x.begin());
    std::copy(w.v.begin(), w.v.end(), good_v.begin());
    std::string failure;
    try {
      sim.step();
    } catch (const std::runtime_error& e) {
      // A failure inside the step (the voxel region outgrew its cap during a rebuild).
      failure = e.what();
    }
    if (failure.empty() && !finite_state(w)) {
      int bad = 0;
      while (bad < n && w.x[bad].allFinite() && w.v[bad].allFinite()) ++bad;
      std::string body;
      for (const Body& b : w.bodies)
        if (bad >= b.begin && bad < b.end) body = b.name;
      failure = "state not finite (body " + body + ", node " + std::to_string(bad) + ")";
    }
    if (!failure.empty()) {
      error = "step " + std::to_string(s) + ": " + failure + "; last good state is step " +
              std::to_string(s - 1);
      std::fprintf(stderr, "harness: simulation failed: %s\n", error.c_str());
      status = "error";
      exit_code = 3;
      std::copy(good_x.begin(), good_x.end(), w.x.begin());
      std::copy(good_v.begin(), good_v.end(), w.v.begin());
      sim.step_index = s - 1;
      sim.time = (s - 1) * scene.dt;
      break;
    }
    const bool measure_now = want_refs && s % scene.references.every == 0;
    const double ke = sim.kinetic_energy();
    ke_peak = std::max(ke_peak, ke);
    const double pe = sim.potential_energy();
    t_step.push_back(sim.last.step_us);
    t_phys.push_back(sim.last.physics_us);
    if (!sim.pairs.empty() && scene.has(kContact)) {
      t_det.push_back(sim.last.detect_us);
      t_elim.push_back(sim.last.eliminate_us);
    }
    if (sim.pairs.empty()) steps.row(sim, nullptr, nullptr, ke, pe);
    for (std::size_t pi = 0; pi < sim.pairs.size(); ++pi) {
      PairSlot& p = sim.pairs[pi];
      PairTotals& t = totals[pi];
      t.contacts_total += p.contacts;
      const Measurement* m = nullptr;
      if (measure_now) {
        static const std::vector<Contact> none;
        meas[pi] = Measurement{};
        measurers[pi]->measure(w, p.spec, p.collision ? p.collision->contacts() : none, meas[pi]);
        m = &meas[pi];
        if (m->has_cgal && m->pen_guest && m->pen_host) {
          if (pen_step != s)
            for (auto& f : pen_flags) std::fill(f.begin(), f.end(), 0);
          pen_step = s;
          track(pi, 0, *m->pen_guest, s);
          track(pi, 1, *m->pen_host, s);
        }
        if (m->has_cgal) {
          t.measured = true;
          t.tp += m->tp;
          t.fp += m->fp;
          t.fn += m->fn;
          t.true_pen_final = m->true_pen_guest + m->true_pen_host;
          t.max_depth_final = m->max_depth;
          t.max_depth_peak = std::max(t.max_depth_peak, m->max_depth);
          t_cgal.push_back(m->t_cgal_us);
        }
        if (m->has_fcl) t_fcl.push_back(m->t_fcl_us);
      }
      steps.row(sim, &p, m, ke, pe);
    }
    if (scene.frames_every > 0 && s % scene.frames_every == 0 && s != scene.steps) write_frames(s);
    if (tty) {
      const auto now = std::chrono::steady_clock::now();
      if (now - last_progress > std::chrono::milliseconds(200) || s == scene.steps) {
        last_progress = now;
        std::fprintf(stderr, "\r%s: step %d/%d (%.0f us/step)   ", scene.name.c_str(), s, scene.steps,
                     sim.last.step_us);
      }
    }
  }
  if (tty) std::fprintf(stderr, "\n");
  write_frames(sim.step_index);
  steps.close();
  if (want_refs && scene.references.cgal) {
    // One row per episode of true penetration: a node found penetrating on consecutive
    // measured steps. `steps` counts simulation steps from the first to the last measured step
    // it was found penetrating, plus `every` (the resolution of the measurement); `open` = still
    // penetrating when the run ended (a censored episode).
    std::ofstream ep(dir / "penetration_episodes.csv");
    ep << "pair,body,node,first_step,last_step,steps,open\n";
    for (const Episode& e : episodes)
      ep << sim.pairs[e.pair].label << "," << w.bodies[e.body].name << "," << e.node << "," << e.first << ","
         << e.last << "," << (e.last - e.first + scene.references.every) << "," << (e.open ? 1 : 0) << "\n";
    if (!ep) throw std::runtime_error("cannot write penetration_episodes.csv");
  }

  json sum;
  sum["scene"] = scene.name;
  sum["scene_file"] = scene.file;
  sum["status"] = status;
  sum["error"] = error.empty() ? json(nullptr) : json(error);
  sum["steps_run"] = sim.step_index;
  sum["finite"] = exit_code == 0;
  sum["effects"] = sim.effects_simulated();
  sum["git_commit"] = HARNESS_GIT_COMMIT;
  json ver = {{"compiler", compiler_version()}, {"Eigen", eigen_version()}};
  for (const auto& [k, v] : opt.versions) ver[k] = v;
  sum["versions"] = ver;
  sum["resolved_scene"] = scene.resolved;
  sum["state_hash"] = state_hash(w);
  sum["timing_us"] = {{"step", num_or_null(median(t_step))},       {"physics", num_or_null(median(t_phys))},
                      {"detect", num_or_null(median(t_det))},      {"eliminate", num_or_null(median(t_elim))},
                      {"cgal", num_or_null(median(t_cgal))},       {"fcl", num_or_null(median(t_fcl))}};
  sum["stability"] = {{"integrator", scene.integrator == Integrator::symplectic_euler ? "symplectic_euler" : "implicit_euler"},
                      {"dt", scene.dt},
                      {"dt_crit", num_or_null(sim.dt_crit)},
                      {"dt_crit_min", num_or_null(sim.dt_crit_min)},
                      {"guard", scene.guard == Guard::refuse ? "refuse" : "substep"},
                      {"guard_every_steps", Simulation::kGuardEvery},
                      {"substeps", sim.substeps},
                      {"max_substeps", sim.max_substeps},
                      {"guard_violations", sim.guard_violations}};
  if (scene.integrator == Integrator::implicit_euler)
    sum["stability"]["implicit"] = {{"cg_max_iterations", sim.implicit_max_iterations},
                                    {"cg_unconverged_solves", sim.implicit_unconverged}};
  sum["nodes"] = w.num_nodes();
  sum["springs"] = w.springs.size();
  sum["kinetic_energy_final"] = sim.kinetic_energy();
  sum["kinetic_energy_peak"] = ke_peak;
  json pairs = json::array();
  for (std::size_t pi = 0; pi < sim.pairs.size(); ++pi) {
    // (axes were recorded from the rest state before the first step)
    const PairSlot& p = sim.pairs[pi];
    const PairTotals& t = totals[pi];
    json pj;
    pj["pair"] = p.label;
    pj["detector"] = p.collision ? json(p.spec.detector) : json(nullptr);
    pj["voxel_size_used"] = p.collision && p.collision->voxel_size() > 0.0 ? json(p.collision->voxel_size())
                                                                            : json(nullptr);
    pj["region_rebuilds"] = p.collision ? json(p.collision->rebuilds()) : json(nullptr);
    pj["contacts_total"] = t.contacts_total;
    pj["tunnelled"] = tunnelled_nodes(w, p.spec, axes[pi]);
    pj["true_pen_final"] = t.measured ? json(t.true_pen_final) : json(nullptr);
    pj["max_depth_final"] = t.measured ? json(t.max_depth_final) : json(nullptr);
    pj["max_depth_peak"] = t.measured ? json(t.max_depth_peak) : json(nullptr);
    pj["recall"] = t.measured && t.tp + t.fn > 0 ? json(double(t.tp) / double(t.tp + t.fn)) : json(nullptr);
    pj["precision"] = t.measured && t.tp + t.fp > 0 ? json(double(t.tp) / double(t.tp + t.fp)) : json(nullptr);
    pairs.push_back(pj);
  }
  sum["pairs"] = pairs;
  write_json_atomic(dir / "summary.json", sum);
  return exit_code;
}

}  // namespace harness
