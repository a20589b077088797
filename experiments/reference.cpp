#include "experiments/reference.hpp"

#include "core/run/surfaces.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

namespace harness {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

double default_stiffness(const Scene& sc) {
  if (sc.contacts.empty()) return 0.0;
  if (sc.contacts[0].spec.force_rule == ForceRule::penalty && sc.contacts[0].spec.stiffness > 0.0)
    return sc.contacts[0].spec.stiffness;
  for (const BodySpec& b : sc.bodies)
    if (b.name == sc.contacts[0].host)
      return 100.0 * (b.material.youngs_modulus > 0.0 ? 0.6 * b.material.youngs_modulus * 0.005 : b.material.stiffness);
  return 500.0;
}

// The scene of level i: exact detection, penalty k, contact both ways, dt / 2^i, a tight settle.
Scene level_scene(const Scene& base, int level, double k) {
  json s = rescale_dt(base, 1 << level).resolved;
  const double tol = base.settle.present ? base.settle.tolerance / 100.0 : 1e-5;
  const long long max_steps = base.settle.present ? 4LL * base.settle.max_steps : 20LL * std::max(1, base.steps);
  s["time"]["settle"] = {{"tolerance", tol}, {"max_steps", max_steps * (1 << level)}};
  bool contact = false;
  for (const auto& e : s["effects"]) contact = contact || e == "contact";
  if (!contact) s["effects"].push_back("contact");
  for (json& c : s["contacts"]) {
    c["detector"] = "cgal";
    c["eliminator"] = "line";
    c["force"] = {{"stiffness", k}};
    c["two_sided"] = true;
  }
  return scene_from_json(s, base.file, base.dir);
}

double max_change(const SurfaceState& a, const SurfaceState& b) {
  double m = 0.0;
  for (std::size_t i = 0; i < a.x.size(); ++i)
    for (std::size_t j = 0; j < a.x[i].size(); ++j) m = std::max(m, (a.x[i][j] - b.x[i][j]).norm());
  return m;
}

}  // namespace

int run_reference(const Scene& scene, const ReferenceOptions& opt) {
  if (scene.contacts.empty()) throw InputError(scene.file + ": contacts", "a reference solution needs a contact pair");
  if (!opt.run.exact_detectors) throw InputError("harness reference", "this program has no exact detectors (CGAL)");
  const double k0 = opt.stiffness > 0.0 ? opt.stiffness : default_stiffness(scene);
  const fs::path dir(opt.out_dir);
  fs::create_directories(dir);
  fs::remove(dir / "summary.json");
  json levels = json::array();
  SurfaceState previous;
  bool converged = false;
  int last = -1, code = 0;
  for (int level = 0; level < opt.max_levels && !converged; ++level) {
    const double k = k0 * (1 << level);
    const Scene sc = level_scene(scene, level, k);
    RunOptions ro = opt.run;
    ro.out_dir = (dir / "levels" / std::to_string(level)).string();
    ro.progress = opt.progress;
    const auto t0 = std::chrono::steady_clock::now();
    code = run_scene(sc, ro);
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::ifstream in(fs::path(ro.out_dir) / "summary.json");
    const json sum = json::parse(in);
    const SurfaceState state = read_surfaces((fs::path(ro.out_dir) / "surfaces.csv").string());
    json row = {{"level", level},           {"dt", sc.dt},
                {"stiffness", k},           {"steps_run", sum["steps_run"]},
                {"settled", sum["settled"]}, {"residual", sum["residual"]},
                {"wall_s", wall},           {"change_max", nullptr}};
    if (level > 0) {
      const double change = max_change(state, previous);
      row["change_max"] = change;
      converged = change < opt.tolerance && sum["settled"] == true;
    }
    std::fprintf(stderr, "reference: level %d (dt %.3g s, k_c %.4g N/m): %s after %d steps, change %s\n", level, sc.dt, k,
                 sum["settled"] == true ? "settled" : "NOT settled", sum["steps_run"].get<int>(),
                 level > 0 ? (std::to_string(row["change_max"].get<double>() * 1e3) + " mm").c_str() : "-");
    levels.push_back(row);
    previous = state;
    last = level;
    if (code != 0) break;
  }
  // The last level's run is the reference: copied to DIR, its summary with the loop's record.
  const fs::path src = dir / "levels" / std::to_string(last);
  for (const char* f : {"steps.csv", "surfaces.csv", "penetration_episodes.csv"})
    if (fs::exists(src / f)) fs::copy_file(src / f, dir / f, fs::copy_options::overwrite_existing);
  if (fs::exists(src / "frames")) {
    fs::remove_all(dir / "frames");
    fs::copy(src / "frames", dir / "frames", fs::copy_options::recursive);
  }
  std::ifstream in(src / "summary.json");
  json sum = json::parse(in);
  sum["reference"] = {{"converged", converged},
                      {"tolerance", opt.tolerance},
                      {"base_dt", scene.dt},
                      {"base_stiffness", k0},
                      {"max_levels", opt.max_levels},
                      {"levels", levels}};
  std::ofstream out(dir / "summary.json.tmp");
  out << sum.dump(2) << "\n";
  out.close();
  fs::rename(dir / "summary.json.tmp", dir / "summary.json");
  if (!converged)
    std::fprintf(stderr, "harness: warning: the reference of %s did not converge within %d levels (tolerance %g m)\n",
                 scene.name.c_str(), opt.max_levels, opt.tolerance);
  return code;
}

}  // namespace harness
