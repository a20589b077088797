#include "core/run/summary.hpp"

#include "core/run/compare.hpp"

#include "harness_git.hpp"

#include <algorithm>
#include <climits>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace harness {

namespace fs = std::filesystem;
using nlohmann::json;

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

// A figure over the final window (run/window.hpp): null when it was never measured there.
json stat_json(const WindowStat& w) {
  if (w.n == 0) return nullptr;
  return {{"mean", num_or_null(w.mean)}, {"max", num_or_null(w.max)}, {"min", num_or_null(w.min)},
          {"amplitude", num_or_null(w.amplitude())}, {"measured_steps", w.n}};
}

json window_json(const StabilityJudgement& j) {
  const WindowSpan& w = j.span;
  return {{"from_step", w.from},
          {"to_step", w.to},
          {"steps", w.steps()},
          {"forcing_ends_step", w.forcing_end == INT_MAX ? json(nullptr) : json(w.forcing_end)},
          {"after_forcing", w.after_forcing},
          {"contact_power_W", num_or_null(j.contact_power)},
          {"input_power_W", num_or_null(j.input_power)},
          {"contact_power_ratio", num_or_null(j.ratio)},
          {"injection_ratio_limit", kInjectionRatio},
          {"kinetic_growth", num_or_null(j.growth)},
          {"net_contact_work_J", num_or_null(j.net_contact_work)},
          {"energy_in_J", num_or_null(j.energy_in)},
          {"energy_scale_J", num_or_null(j.energy_scale)},
          {"kick_share_limit", kKickShare},
          {"kicked", j.kicked},
          {"growth_limit", kGrowthFactor},
          {"kinetic_energy", stat_json(j.kinetic)},
          {"residual", stat_json(j.residual)}};
}

json stability_json(const Simulation& sim) {
  const Scene& sc = sim.scene();
  const SimulationStats& st = sim.stats();
  json j = {{"integrator", sc.integrator == Integrator::symplectic_euler ? "symplectic_euler" : "implicit_euler"},
            {"dt", sc.dt},
            {"dt_crit", num_or_null(st.stability.dt_crit)},
            {"dt_crit_min", num_or_null(st.stability.dt_crit_min)},
            {"guard", sc.guard == Guard::refuse ? "refuse" : "substep"},
            {"guard_every_steps", StabilityGuard::kEvery},
            {"substeps", st.stability.substeps},
            {"max_substeps", st.stability.max_substeps},
            {"guard_violations", st.stability.guard_violations}};
  if (sc.integrator == Integrator::implicit_euler)
    j["implicit"] = {{"cg_max_iterations", st.implicit_max_iterations},
                     {"cg_unconverged_solves", st.implicit_unconverged}};
  return j;
}

json pair_json(const Simulation& sim, const Recorder& rec, std::size_t pi) {
  const Pair& p = sim.pairs()[pi];
  const PairTotals& t = rec.totals()[pi];
  auto measured = [&](json v) { return t.measured ? v : json(nullptr); };
  json pj;
  pj["pair"] = p.label;
  pj["detector"] = p.collision        ? json(to_string(p.spec.detector))
                   : p.engine_contact ? json(p.engine_contact)
                                      : json(nullptr);
  pj["voxel_size_used"] =
      p.collision && p.collision->voxel_size() > 0.0 ? json(p.collision->voxel_size()) : json(nullptr);
  pj["region_rebuilds"] = p.collision ? json(p.collision->rebuilds()) : json(nullptr);
  pj["contacts_total"] = t.contacts_total;
  // Detectors with a guaranteed band (voxel_exact): contacts found beyond it, over the run and
  // the most in one step; null for the others.
  pj["beyond_band_total"] = t.has_band ? json(t.beyond_band_total) : json(nullptr);
  pj["beyond_band_peak"] = t.has_band ? json(t.beyond_band_peak) : json(nullptr);
  // Nodes that have passed through the other body (CGAL; null without it).
  const TunnelCount tun = rec.tunnel_count(pi);
  pj["tunnelled"] = tun.measured ? json(tun.guest) : json(nullptr);
  pj["tunnelled_host"] = tun.measured ? json(tun.host) : json(nullptr);
  pj["tunnelled_peak"] = measured(json{{"guest", t.tunnelled_guest_peak}, {"host", t.tunnelled_host_peak}});
  pj["true_pen_final"] = measured(t.true_pen_final);
  pj["max_depth_final"] = measured(t.max_depth_final);
  pj["max_depth_peak"] = measured(t.max_depth_peak);
  // Stated values where the ratio is 0/0: nothing truly penetrated, so nothing was missed
  // (recall 1); nothing was reported, so nothing was reported falsely (precision 1). Neither
  // says the bodies are where they should be: that is error_vs_reference. Guest and host nodes
  // apart: a one-sided detector reports no host node, so any penetrating host node is a miss.
  auto ratio = [&](long long a, long long b) { return t.measured ? json(b > 0 ? double(a) / double(b) : 1.0) : json(nullptr); };
  pj["recall"] = ratio(t.tp, t.tp + t.fn);
  pj["precision"] = ratio(t.tp, t.tp + t.fp);
  pj["recall_host"] = ratio(t.tp_host, t.tp_host + t.fn_host);
  pj["precision_host"] = ratio(t.tp_host, t.tp_host + t.fp_host);
  pj["measured_steps"] = static_cast<long long>(rec.series()[pi].tunnelled.size());
  const WindowSpan span = rec.judge(sim, false).span;
  const PairSeries& ser = rec.series()[pi];
  pj["window"] = {{"depth_max", stat_json(ser.depth_max.over(span))},
                  {"true_pen", stat_json(ser.true_pen.over(span))},
                  {"tunnelled", stat_json(ser.tunnelled.over(span))}};
  return pj;
}

}  // namespace

json summary_json(const Simulation& sim, const Recorder& rec, const RunStatus& status,
                  const std::map<std::string, std::string>& versions) {
  const Scene& sc = sim.scene();
  const World& w = sim.world();
  const RunTimings& t = rec.timings();
  json sum;
  sum["scene"] = sc.name;
  sum["scene_file"] = sc.file;
  sum["status"] = status.status;
  sum["error"] = status.error.empty() ? json(nullptr) : json(status.error);
  sum["steps_run"] = sim.step_index();
  sum["finite"] = status.finite;
  sum["effects"] = sim.effects_simulated();
  sum["git_commit"] = HARNESS_GIT_COMMIT;
  json ver = {{"compiler", compiler_version()}, {"Eigen", eigen_version()}};
  for (const auto& [k, v] : versions) ver[k] = v;
  sum["versions"] = ver;
  sum["resolved_scene"] = sc.resolved;
  sum["state_hash"] = state_hash(w);
  sum["timing_us"] = {{"step", num_or_null(median(t.step))},       {"physics", num_or_null(median(t.physics))},
                      {"detect", num_or_null(median(t.detect))},   {"eliminate", num_or_null(median(t.eliminate))},
                      {"cgal", num_or_null(median(t.cgal))},       {"fcl", num_or_null(median(t.fcl))}};
  sum["stability"] = stability_json(sim);
  const StabilityJudgement judged = rec.judge(sim, sc.settle.present && status.settled);
  sum["window"] = window_json(judged);
  sum["stability_verdict"] = status.status == "ok" || status.status == "interrupted" ? json(judged.verdict) : json("failed");
  sum["nodes"] = w.num_nodes();
  sum["springs"] = w.springs.size();
  sum["kinetic_energy_final"] = sim.kinetic_energy();
  sum["kinetic_energy_peak"] = rec.kinetic_energy_peak();
  const EnergyLedger& e = sim.energy();
  sum["energy"] = {{"energy_kinetic", e.kinetic},         {"energy_elastic", e.elastic},
                   {"work_external", e.work_external},    {"energy_dissipated", e.dissipated},
                   {"work_contact", e.work_contact},      {"energy_balance_error", e.balance_error()},
                   {"work_contact_peak", e.work_contact_peak}, {"energy_initial", e.initial}};
  if (sim.engine()) {
    // A peer engine's work is not booked (simulation.hpp): only the energies are known.
    for (const char* k : {"work_external", "energy_dissipated", "work_contact", "energy_balance_error", "work_contact_peak"})
      sum["energy"][k] = nullptr;
    sum["engine"] = sim.engine()->describe();
  } else {
    sum["engine"] = {{"name", "harness"}};
  }
  sum["settled"] = sc.settle.present ? json(status.settled) : json(nullptr);
  sum["residual"] = num_or_null(sim.residual());
  sum["settle_steps"] = status.settle_steps;
  json pairs = json::array();
  for (std::size_t pi = 0; pi < sim.pairs().size(); ++pi) pairs.push_back(pair_json(sim, rec, pi));
  sum["pairs"] = pairs;
  return sum;
}

void add_comparison(json& sum, const Simulation& sim, const Recorder& rec, const Comparison& cmp) {
  const auto conv = cmp.converged();
  sum["compare"] = {{"dir", cmp.dir()},
                    {"kind", cmp.is_reference() ? "reference" : "run"},
                    {"converged", conv ? json(*conv) : json(nullptr)},
                    {"touch_tolerance", kTouchTolerance},
                    {"final_signed_distance_measured", rec.sd_step() == sim.step_index()},
                    {"against", cmp.has_trajectory() ? "the reference's state at the same step (its trajectory)"
                                                     : "the reference's final state"}};
  const std::vector<ReferenceErrors> errs = rec.final_errors(sim);
  const WindowSpan span = rec.judge(sim, false).span;
  for (std::size_t p = 0; p < errs.size(); ++p) {
    const ReferenceErrors& e = errs[p];
    const bool sd = rec.sd_step() == sim.step_index() && e.distances;
    const PairTotals& t = rec.totals()[p];
    const PairSeries& ser = rec.series()[p];
    const TunnelCount tun = rec.tunnel_count(p);
    sum["pairs"][p]["error_vs_reference"] = {
        {"pos_err_max", e.pos_err_max},
        {"pos_err_rms", e.pos_err_rms},
        {"gap_max", sd ? json(e.gap_max) : json(nullptr)},
        {"gap_mean", sd ? json(e.gap_mean) : json(nullptr)},
        {"depth_max", sd ? json(e.depth_max) : json(nullptr)},
        {"depth_peak", t.measured ? json(std::max(t.max_depth_peak, sd ? e.depth_max : 0.0)) : json(nullptr)},
        {"tunnelled_guest", tun.measured ? json(tun.guest) : json(nullptr)},
        {"tunnelled_host", tun.measured ? json(tun.host) : json(nullptr)},
        {"tunnelled_peak", t.measured ? json(std::max(t.tunnelled_guest_peak + t.tunnelled_host_peak, tun.guest + tun.host))
                                      : json(nullptr)},
        {"touching_nodes", e.touching},
        {"window", {{"pos_err_max", stat_json(ser.pos_err_max.over(span))},
                    {"pos_err_rms", stat_json(ser.pos_err_rms.over(span))},
                    {"gap_max", stat_json(ser.gap_max.over(span))},
                    {"gap_mean", stat_json(ser.gap_mean.over(span))},
                    {"depth_max", stat_json(ser.depth_max.over(span))},
                    {"tunnelled", stat_json(ser.tunnelled.over(span))}}}};
  }
}

void write_summary(const std::string& dir, const json& summary) {
  const fs::path path = fs::path(dir) / "summary.json";
  const fs::path tmp = path.string() + ".tmp";
  {
    std::ofstream o(tmp);
    o << summary.dump(2) << "\n";
    if (!o) throw std::runtime_error("cannot write " + tmp.string());
  }
  fs::rename(tmp, path);
}

void write_episodes(const std::string& dir, const Simulation& sim, const Recorder& rec) {
  // `steps` counts simulation steps from the first to the last measured step the node was found
  // penetrating, plus `every` (the resolution of the measurement); `open` = still penetrating
  // when the run ended (a censored episode).
  const int every = sim.scene().references.every;
  std::ofstream ep(fs::path(dir) / "penetration_episodes.csv");
  ep << "pair,body,node,first_step,last_step,steps,open\n";
  for (const Episode& e : rec.episodes())
    ep << sim.pairs()[e.pair].label << "," << sim.world().bodies[e.body].name << "," << e.node << "," << e.first
       << "," << e.last << "," << (e.last - e.first + every) << "," << (e.open ? 1 : 0) << "\n";
  if (!ep) throw std::runtime_error("cannot write penetration_episodes.csv");
}

}  // namespace harness
