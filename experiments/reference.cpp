#include "experiments/reference.hpp"

#include "core/collision/responses/force_rule.hpp"
#include "core/run/summary.hpp"
#include "core/run/summary_keys.hpp"
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
  // The scene's own linear penalty, when it has one (the reference is a penalty's).
  const ContactSpec& c = sc.contacts[0].spec;
  if (c.force_rule == kDefaultObjectRule && rule_parameter(c, "stiffness") > 0.0) return rule_parameter(c, "stiffness");
  for (const BodySpec& b : sc.bodies)
    if (b.name == sc.contacts[0].host)
      return 100.0 * (b.material.youngs_modulus > 0.0 ? 0.6 * b.material.youngs_modulus * 0.005 : b.material.stiffness);
  return 500.0;
}

// The scene of level i: exact detection, penalty k, contact both ways (or one), dt / 2^i, the
// guard substepping wherever dt_crit requires it, the scene's own settling tolerance.
// The base scene's document edited, validated once.
Scene level_scene(const Scene& base, int level, double k, bool one_sided) {
  json s = base.resolved;
  rescale_steps(s, 1 << level);
  const double tol = base.settle.present ? base.settle.tolerance : 1e-5;
  const long long max_steps = base.settle.present ? 4LL * base.settle.max_steps : 20LL * std::max(1, base.steps);
  s["time"]["settle"] = {{"tolerance", tol}, {"max_steps", max_steps * (1 << level)}};
  s["time"]["guard"] = scene_word(Guard::substep);
  bool contact = false;
  for (const auto& e : s["effects"]) contact = contact || e == "contact";
  if (!contact) s["effects"].push_back("contact");
  for (json& c : s["contacts"]) {
    c["detector"] = "cgal";
    c["eliminator"] = "line";
    c["force"] = {{"stiffness", k}};
    c["two_sided"] = !one_sided;
  }
  return scene_from_json(s, base.file, base.dir);
}

double max_change(const SurfaceState& a, const SurfaceState& b) {
  double m = 0.0;
  for (std::size_t i = 0; i < a.x.size(); ++i)
    for (std::size_t j = 0; j < a.x[i].size(); ++j) m = std::max(m, (a.x[i][j] - b.x[i][j]).norm());
  return m;
}

// A level's row of the loop's record (summary.json reference.levels).
json level_row(int level, const Scene& sc, double k, const RunOutcome& lv, double wall) {
  const StabilityStats& st = lv.stability;
  return {{"level", level},           {"dt", sc.dt},
          {"stiffness", k},           {"steps_run", lv.steps_run},
          {"settled", lv.status.settled}, {"residual", number_or_null(lv.residual)},
          {"wall_s", wall},           {"change_max", nullptr},
          {"order", nullptr},         {"error_estimate", nullptr},
          {"dt_crit", number_or_null(st.dt_crit)}, {"dt_crit_min", number_or_null(st.dt_crit_min)},
          {"max_substeps", st.max_substeps}, {"guard_violations", st.guard_violations},
          {"stability_verdict", lv.verdict}};
}

// A level's change from the one before, and from the last two changes the observed order and
// Richardson's estimate of this level's error.
void add_change(json& row, const json& levels, int level, double change) {
  row["change_max"] = change;
  if (level > 1 && levels.back()["change_max"].is_number()) {
    const double before = levels.back()["change_max"].get<double>();
    if (change > 0.0 && before > 0.0) {
      const double p = std::log2(before / change);
      row["order"] = p;
      if (p > 0.0) row["error_estimate"] = change / (std::exp2(p) - 1.0);
    }
  }
}

// The last level's run is the reference: its files copied to DIR.
void copy_last_level(const fs::path& dir, const fs::path& src) {
  for (const char* f : {"steps.csv", "timing.csv", "surfaces.csv", "penetration_episodes.csv"})
    if (fs::exists(src / f)) fs::copy_file(src / f, dir / f, fs::copy_options::overwrite_existing);
  if (fs::exists(src / "frames")) {
    fs::remove_all(dir / "frames");
    fs::copy(src / "frames", dir / "frames", fs::copy_options::recursive);
  }
}

// The floor: how far the answer may be from the converged one. The last level's change when the
// last order is sane (kSaneOrder: first order in dt and 1/k_c is what the loop expects; the change
// then bounds the remaining error); else the largest of the last two changes (not yet asymptotic:
// a jump between levels stays possible); null with one level. (scripts/harness_results/reader.py
// reads it, and applies the same rule to references made before it was recorded.) With its rule.
std::pair<json, std::string> reference_floor(const json& levels) {
  constexpr double kSaneOrder[2] = {0.5, 4.0};
  std::vector<double> changes;
  for (const json& lv : levels)
    if (lv["change_max"].is_number()) changes.push_back(lv["change_max"].get<double>());
  if (changes.empty()) return {nullptr, "one level only"};
  const json& lo = levels.back()["order"];
  if (lo.is_number() && lo.get<double>() >= kSaneOrder[0] && lo.get<double>() <= kSaneOrder[1])
    return {changes.back(), "last change (order sane)"};
  return {changes.size() > 1 ? std::max(changes[changes.size() - 2], changes.back()) : changes.back(),
          lo.is_number() ? "largest of the last two changes (order not sane)" : "largest change (no order yet)"};
}

// What the reference knows, printed: its floor, the observed order and Richardson's estimate of
// the last level's error where three levels gave an order; a warning when it did not converge.
void print_reference_end(const Scene& scene, const ReferenceOptions& opt, bool converged, std::size_t n_levels,
                         const json& floor, const std::string& floor_rule, const json& order, const json& estimate) {
  auto shown = [](const json& v, double scale, const char* unit) {
    if (!v.is_number()) return std::string("-");
    char b[64];
    std::snprintf(b, sizeof b, "%.3g%s", v.get<double>() * scale, unit);
    return std::string(b);
  };
  std::fprintf(stderr, "reference: %s after %d levels; floor %s (%s), observed order %s, Richardson error estimate %s\n",
               converged ? "converged" : "NOT converged", static_cast<int>(n_levels), shown(floor, 1e3, " mm").c_str(),
               floor_rule.c_str(), shown(order, 1.0, "").c_str(), shown(estimate, 1e3, " mm").c_str());
  if (!converged)
    std::fprintf(stderr, "harness: warning: the reference of %s did not converge within %d levels (tolerance %g m)\n",
                 scene.name.c_str(), opt.max_levels, opt.tolerance);
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
    const Scene sc = level_scene(scene, level, k, opt.one_sided);
    RunOptions ro = opt.run;
    ro.out_dir = (dir / "levels" / std::to_string(level)).string();
    ro.progress = opt.progress;
    const auto t0 = std::chrono::steady_clock::now();
    RunOutcome lv;
    code = run_scene(sc, ro, &lv);
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const SurfaceState state = read_surfaces((fs::path(ro.out_dir) / "surfaces.csv").string());
    const StabilityStats& st = lv.stability;
    json row = level_row(level, sc, k, lv, wall);
    if (level > 0) {
      add_change(row, levels, level, max_change(state, previous));
      converged = row["change_max"].get<double>() < opt.tolerance && lv.status.settled && level + 1 >= opt.min_levels &&
                  st.guard_violations == 0;
    }
    std::fprintf(stderr, "reference: level %d (dt %.3g s, k_c %.4g N/m, substeps up to %d): %s after %d steps, change %s\n",
                 level, sc.dt, k, st.max_substeps, lv.status.settled ? "settled" : "NOT settled", lv.steps_run,
                 level > 0 ? (std::to_string(row["change_max"].get<double>() * 1e3) + " mm").c_str() : "-");
    levels.push_back(row);
    previous = state;
    last = level;
    if (code != 0) break;
  }
  const fs::path src = dir / "levels" / std::to_string(last);
  copy_last_level(dir, src);
  std::ifstream in(src / "summary.json");
  json sum = json::parse(in);
  // The order over the levels: the last observed one (null before three levels).
  json order = nullptr, estimate = nullptr;
  for (const json& lv : levels)
    if (lv["order"].is_number()) order = lv["order"], estimate = lv["error_estimate"];
  const auto [floor, floor_rule] = reference_floor(levels);
  sum[json::json_pointer(summary_key::kReference)] = {{"converged", converged},
                      {"tolerance", opt.tolerance},
                      {"min_levels", opt.min_levels},
                      {"two_sided", !opt.one_sided},
                      {"order", order},
                      {"error_estimate", estimate},
                      {"floor", floor},
                      {"floor_rule", floor_rule},
                      {"base_dt", scene.dt},
                      {"base_stiffness", k0},
                      {"max_levels", opt.max_levels},
                      {"levels", levels}};
  std::ofstream out(dir / "summary.json.tmp");
  out << sum.dump(2) << "\n";
  out.close();
  fs::rename(dir / "summary.json.tmp", dir / "summary.json");
  print_reference_end(scene, opt, converged, levels.size(), floor, floor_rule, order, estimate);
  return code;
}

}  // namespace harness
