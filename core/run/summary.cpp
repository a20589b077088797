#include "core/run/summary.hpp"

#include "core/run/step_stats.hpp"

#include "core/run/compare.hpp"
#include "core/run/machine.hpp"
#include "core/parallel.hpp"
#include "core/run/summary_keys.hpp"

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
namespace key = summary_key;

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

json num_or_null(double v) { return number_or_null(v); }

// The value at a JSON pointer (summary_keys.hpp), made if missing.
json& at(json& j, const char* pointer) { return j[json::json_pointer(pointer)]; }
json& at(json& j, const std::string& pointer) { return j[json::json_pointer(pointer)]; }

// A figure over the final window (run/window.hpp): null when it was never measured there.
json stat_json(const WindowStat& w) {
  if (w.n == 0) return nullptr;
  return {{"mean", num_or_null(w.mean)}, {"max", num_or_null(w.max)}, {"min", num_or_null(w.min)},
          {"amplitude", num_or_null(w.amplitude())}, {"measured_steps", w.n}};
}

json thresholds_json() {
  json t = json::object();
  for (const ThresholdDoc& d : kStabilityThresholds) t[d.name] = d.value;
  return t;
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
          {"input_period_s", num_or_null(j.input_period)},
          {key::kContactPowerRatio, num_or_null(j.ratio)},
          {"injection_ratio_limit", kInjectionRatio},
          {"kinetic_growth", num_or_null(j.growth)},
          {"net_contact_work_J", num_or_null(j.net_contact_work)},
          {"energy_in_J", num_or_null(j.energy_in)},
          {"energy_scale_J", num_or_null(j.energy_scale)},
          {"kick_share_limit", kKickShare},
          {"kicked", j.kicked},
          {"growth_limit", kGrowthFactor},
          // The class's own figures (window.hpp) and its thresholds, one table.
          {"time_scale_s", num_or_null(j.time_scale)},
          {"chatter_amplitude_m", num_or_null(j.inputs.chatter_amplitude)},
          {"chatter_length_m", num_or_null(j.inputs.chatter_length)},
          {"chatter_length_from", j.inputs.chatter_length_from},
          {"stored_energy_J", num_or_null(j.stored_energy)},
          {"contact_input_share", num_or_null(j.contact_input_share)},
          {"growth_floor_J", num_or_null(j.growth_floor)},
          {"thresholds", thresholds_json()},
          {"kinetic_energy", stat_json(j.kinetic)},
          {"residual", stat_json(j.residual)}};
}

json stability_json(const Simulation& sim) {
  const Scene& sc = sim.scene();
  const SimulationStats& st = sim.stats();
  json j = {{"integrator", scene_word(sc.integrator)},
            {"dt", sc.dt},
            {"dt_crit", num_or_null(st.stability.dt_crit)},
            {"dt_crit_min", num_or_null(st.stability.dt_crit_min)},
            {"guard", scene_word(sc.guard)},
            {"guard_every_steps", StabilityGuard::kEvery},
            {"substeps", st.stability.substeps}};
  if (sc.integrator == Integrator::implicit_euler)
    j["implicit"] = {{"cg_max_iterations", st.implicit_max_iterations},
                     {"cg_mean_iterations", st.implicit_solves ? json(static_cast<double>(st.implicit_iterations) /
                                                                       static_cast<double>(st.implicit_solves))
                                                                : json(nullptr)},
                     {"cg_solves", st.implicit_solves},
                     {"cg_tolerance", sim.implicit_tolerance()},
                     {"cg_unconverged_solves", st.implicit_unconverged}};
  return j;
}

json pair_json(const Simulation& sim, const Recorder& rec, const RunOutcome& outcome, std::size_t pi) {
  const Pair& p = sim.pairs()[pi];
  const PairTotals& t = rec.totals()[pi];
  auto measured = [&](json v) { return t.measured ? v : json(nullptr); };
  json pj;
  pj["pair"] = p.label;
  pj["detector"] = p.collision        ? json(p.spec.detector)
                   : p.engine_contact ? json(p.engine_contact)
                                      : json(nullptr);
  // A response of the program's own (harness.run(response=...)) instead of the scene's force rule.
  pj["response"] = p.collision && p.collision->has_response() ? json(p.collision->response_name()) : json(nullptr);
  at(pj, key::kVoxelSizeUsed) =
      p.collision && p.collision->voxel_size() > 0.0 ? json(p.collision->voxel_size()) : json(nullptr);
  at(pj, key::kRegionRebuilds) = p.collision ? json(p.collision->rebuilds()) : json(nullptr);
  at(pj, key::kContactsTotal) = t.contacts_total;
  // Detectors with a guaranteed band (voxel_exact): contacts found beyond it, over the run and
  // the most in one step; null for the others.
  pj["beyond_band_total"] = t.has_band ? json(t.beyond_band_total) : json(nullptr);
  pj["beyond_band_peak"] = t.has_band ? json(t.beyond_band_peak) : json(nullptr);
  // Nodes that have passed through the other body (CGAL; null without it).
  const TunnelCount& tun = outcome.pairs[pi].tunnelled;
  at(pj, key::kTunnelled) = tun.measured ? json(tun.guest) : json(nullptr);
  at(pj, key::kTunnelledHost) = tun.measured ? json(tun.host) : json(nullptr);
  pj["tunnelled_peak"] = measured(json{{"guest", t.tunnelled_guest_peak}, {"host", t.tunnelled_host_peak}});
  at(pj, key::kTruePenFinal) = measured(t.true_pen_final);
  at(pj, key::kMaxDepthFinal) = measured(t.max_depth_final);
  at(pj, key::kMaxDepthPeak) = measured(t.max_depth_peak);
  // Stated values where the ratio is 0/0: nothing truly penetrated, so nothing was missed
  // (recall 1); nothing was reported, so nothing was reported falsely (precision 1). Neither
  // says the bodies are where they should be: that is error_vs_reference. Guest and host nodes
  // apart: a one-sided detector reports no host node, so any penetrating host node is a miss.
  auto ratio = [&](long long a, long long b) { return t.measured ? json(b > 0 ? double(a) / double(b) : 1.0) : json(nullptr); };
  at(pj, key::kRecall) = ratio(t.tp, t.tp + t.fn);
  at(pj, key::kPrecision) = ratio(t.tp, t.tp + t.fp);
  pj["recall_host"] = ratio(t.tp_host, t.tp_host + t.fn_host);
  pj["precision_host"] = ratio(t.tp_host, t.tp_host + t.fp_host);
  // The counts behind them, summed over the measured steps (null without CGAL).
  pj["scores"] = t.measured ? json{{"tp", t.tp}, {"fp", t.fp}, {"fn", t.fn}, {"tp_host", t.tp_host},
                                   {"fp_host", t.fp_host}, {"fn_host", t.fn_host}}
                            : json(nullptr);
  pj["measured_steps"] = static_cast<long long>(rec.series()[pi].tunnelled.size());
  const WindowSpan& span = outcome.judged.span;
  const PairSeries& ser = rec.series()[pi];
  // Truly penetrating guest nodes outside the detector's grid region (null without a region).
  pj["outside_region"] = t.has_region ? json(t.outside_region_final) : json(nullptr);
  pj["outside_region_peak"] = t.has_region ? json(t.outside_region_peak) : json(nullptr);
  // The grid's region in voxels over the measured steps (null without a region), and the guest
  // nodes inside its box with the truly penetrating ones among them, summed over those steps.
  pj["region_voxels"] = t.has_region && t.region_samples > 0
                            ? json{{"final", t.region_voxels_final}, {"peak", t.region_voxels_peak},
                                   {"mean", t.region_voxels_sum / static_cast<double>(t.region_samples)},
                                   {"guest_nodes_inside", t.region_guest_sum}, {"penetrating_inside", t.region_pen_sum}}
                            : json(nullptr);
  pj["window"] = {{"depth_max", stat_json(ser.depth_max.over(span))},
                  {"true_pen", stat_json(ser.true_pen.over(span))},
                  {"true_pen_guest", stat_json(ser.true_pen_guest.over(span))},
                  {"outside_region", stat_json(ser.outside_region.over(span))},
                  {"tunnelled", stat_json(ser.tunnelled.over(span))}};
  return pj;
}

}  // namespace

json summary_json(const Simulation& sim, const Recorder& rec, const RunOutcome& outcome,
                  const std::map<std::string, std::string>& versions) {
  const Scene& sc = sim.scene();
  const World& w = sim.world();
  const RunStatus& status = outcome.status;
  const RunTimings& t = rec.timings();
  json sum;
  sum["scene"] = sc.name;
  sum["scene_file"] = sc.file;
  at(sum, key::kStatus) = status.status;
  sum["error"] = status.error.empty() ? json(nullptr) : json(status.error);
  at(sum, key::kSteps) = sim.step_index();
  at(sum, key::kFinite) = status.finite;
  sum["effects"] = sim.effects_simulated();
  sum["git_commit"] = HARNESS_GIT_COMMIT;
  json ver = {{"compiler", compiler_version()}, {"Eigen", eigen_version()}};
  for (const auto& [k, v] : versions) ver[k] = v;
  sum["versions"] = ver;
  // Where it ran, read from the system, and the threads it used (timings depend on both).
  sum["machine"] = machine_info();
  sum["threads"] = threads();
  at(sum, key::kResolvedScene) = sc.resolved;
  at(sum, key::kStateHash) = state_hash(w);
  const char* const* part = key::kTimingParts;  // step, physics, detect, eliminate, cgal, fcl
  json& timing = at(sum, key::kTiming);
  timing = json::object();
  timing[part[0]] = num_or_null(median(t.step));
  timing[part[1]] = num_or_null(median(t.physics));
  timing[part[2]] = num_or_null(median(t.detect));
  timing[part[3]] = num_or_null(median(t.eliminate));
  timing[part[4]] = num_or_null(median(t.cgal));
  timing[part[5]] = num_or_null(median(t.fcl));
  // What the run's measurement and outputs cost, outside the step (the recorder with the
  // references it runs, steps.csv, frames): the mean over the steps (the measured steps are the
  // dear ones, every references.every) and its share of the step's own mean. The energy audit is
  // inside the step (booked in its force and update passes): `harness bench` rows step_audited
  // against step give its share.
  double outside = 0.0, inside = 0.0;
  for (double v : t.outside) outside += v;
  for (double v : t.step) inside += v;
  const double n_out = static_cast<double>(t.outside.size()), n_in = static_cast<double>(t.step.size());
  timing["outside_step_mean"] = n_out > 0 ? num_or_null(outside / n_out) : json(nullptr);
  timing["outside_step_share"] = n_out > 0 && inside > 0.0 ? num_or_null((outside / n_out) / (inside / n_in)) : json(nullptr);
  // The step's and the collision unit's (detection + response) distribution over every step of
  // the run: mean, 99th percentile and maximum beside the median above, and the real-time factors
  // against the scene's dt (the budget: one step of simulated time per step of wall time).
  const StepStats ss = step_stats(t.step);
  std::vector<double> unit(t.detect.size());
  for (std::size_t i = 0; i < unit.size() && i < t.eliminate.size(); ++i) unit[i] = t.detect[i] + t.eliminate[i];
  const StepStats cs = step_stats(unit);
  timing["step_mean"] = num_or_null(ss.mean);
  timing["step_p99"] = num_or_null(ss.p99);
  timing["step_max"] = num_or_null(ss.max);
  timing["steps_timed"] = ss.n;
  timing["contact_mean"] = num_or_null(cs.mean);
  timing["contact_p99"] = num_or_null(cs.p99);
  timing["contact_max"] = num_or_null(cs.max);
  // The unit's two parts apart (a response that needs no detection, the volume restriction, is
  // judged on its own part): mean and 99th percentile of each.
  const StepStats ds = step_stats(t.detect), es = step_stats(t.eliminate);
  timing["detect_mean"] = num_or_null(ds.mean);
  timing["detect_p99"] = num_or_null(ds.p99);
  timing["eliminate_mean"] = num_or_null(es.mean);
  timing["eliminate_p99"] = num_or_null(es.p99);
  sum["budget_us"] = sc.dt * 1e6;
  sum["realtime_factor_mean"] = num_or_null(realtime_factor(sc.dt, ss.mean));
  sum["realtime_factor_p99"] = num_or_null(realtime_factor(sc.dt, ss.p99));
  at(sum, key::kStability) = stability_json(sim);
  at(sum, key::kMaxSubsteps) = outcome.stability.max_substeps;
  at(sum, key::kGuardViolations) = outcome.stability.guard_violations;
  at(sum, key::kWindow) = window_json(outcome.judged);
  at(sum, key::kStabilityVerdict) = outcome.verdict;
  sum["nodes"] = w.num_nodes();
  sum["node_order"] = node_order_name(w.node_order);  // the layout (outputs keep the scene's numbering)
  sum["springs"] = w.springs.size();
  sum["bodies"] = json::array();
  for (const Body& b : w.bodies)
    sum["bodies"].push_back({{"name", b.name}, {"nodes", b.size()}, {"surface_nodes", b.n_surface}});
  at(sum, key::kKineticFinal) = sim.kinetic_energy();
  at(sum, key::kKineticPeak) = rec.kinetic_energy_peak();
  const EnergyLedger& e = sim.energy();
  json& energy = at(sum, key::kEnergy);
  energy = {{"energy_kinetic", e.kinetic},          {"energy_elastic", e.elastic},
            {key::kWorkExternal, e.work_external},   {key::kDissipated, e.dissipated},
            {key::kWorkContact, e.work_contact},     {key::kBalanceError, e.balance_error()},
            {key::kWorkContactPeak, e.work_contact_peak}, {"energy_initial", e.initial},
            // The springs' energy is evaluated on these steps and the last (recorder.hpp); works,
            // kinetic energy and residual on every step.
            {"elastic_every", rec.energy_every()}};
  if (sim.engine()) {
    // A peer engine's work is not booked (simulation.hpp): only the energies are known.
    for (const char* k : {key::kWorkExternal, key::kDissipated, key::kWorkContact, key::kBalanceError, key::kWorkContactPeak})
      energy[k] = nullptr;
    sum["engine"] = sim.engine()->describe();
  } else {
    sum["engine"] = {{"name", "harness"}};
  }
  at(sum, key::kSettled) = sc.settle.present ? json(status.settled) : json(nullptr);
  at(sum, key::kResidual) = num_or_null(outcome.residual);
  at(sum, key::kSettleSteps) = status.settle_steps;
  json pairs = json::array();
  for (std::size_t pi = 0; pi < sim.pairs().size(); ++pi) pairs.push_back(pair_json(sim, rec, outcome, pi));
  at(sum, key::kPairs) = pairs;
  return sum;
}

void add_comparison(json& sum, const Simulation& sim, const Recorder& rec, const Comparison& cmp, RunOutcome& outcome) {
  const auto conv = cmp.converged();
  at(sum, key::kCompare) = {{"dir", cmp.dir()},
                            {"kind", cmp.is_reference() ? "reference" : "run"},
                            {"touch_tolerance", kTouchTolerance},
                            {"final_signed_distance_measured", rec.sd_step() == sim.step_index()},
                            {"against", cmp.has_trajectory() ? "the reference's state at the same step (its trajectory)"
                                                             : "the reference's final state"}};
  at(sum, key::kCompareConverged) = conv ? json(*conv) : json(nullptr);
  const std::vector<ReferenceErrors> errs = rec.final_errors(sim);
  const WindowSpan& span = outcome.judged.span;
  for (std::size_t p = 0; p < errs.size(); ++p) {
    const ReferenceErrors& e = errs[p];
    const bool sd = rec.sd_step() == sim.step_index() && e.distances;
    const PairTotals& t = rec.totals()[p];
    const PairSeries& ser = rec.series()[p];
    PairOutcome& po = outcome.pairs[p];
    const TunnelCount& tun = po.tunnelled;
    po.compared = true;
    po.errors = e;
    po.pos_err_max_window = ser.pos_err_max.over(span);
    json& ev = at(sum, key::pair_key(static_cast<int>(p), key::kErrorVsReference));
    const char* const* fig = key::kErrorFigures;  // pos_err_max, pos_err_rms, gap_max, gap_mean, depth_max
    ev = {{fig[0], e.pos_err_max},
          {fig[1], e.pos_err_rms},
          {fig[2], sd ? json(e.gap_max) : json(nullptr)},
          {fig[3], sd ? json(e.gap_mean) : json(nullptr)},
          {fig[4], sd ? json(e.depth_max) : json(nullptr)},
          {"depth_peak", t.measured ? json(std::max(t.max_depth_peak, sd ? e.depth_max : 0.0)) : json(nullptr)},
          {"tunnelled_guest", tun.measured ? json(tun.guest) : json(nullptr)},
          {"tunnelled_host", tun.measured ? json(tun.host) : json(nullptr)},
          {"tunnelled_peak", t.measured ? json(std::max(t.tunnelled_guest_peak + t.tunnelled_host_peak, tun.guest + tun.host))
                                        : json(nullptr)},
          {"touching_nodes", e.touching},
          {"window", {{"pos_err_max", stat_json(po.pos_err_max_window)},
                      {"pos_err_rms", stat_json(ser.pos_err_rms.over(span))},
                      {"gap_max", stat_json(ser.gap_max.over(span))},
                      {"gap_mean", stat_json(ser.gap_mean.over(span))},
                      {"depth_max", stat_json(ser.depth_max.over(span))},
                      {"tunnelled", stat_json(ser.tunnelled.over(span))}}}};
  }
}

void add_comparison_also(json& sum, const Simulation& sim, const Recorder& rec, const Comparison& cmp,
                         const WindowSpan& span) {
  const std::vector<ReferenceErrors> errs = rec.final_errors_also(sim);
  const auto conv = cmp.converged();
  for (std::size_t p = 0; p < errs.size(); ++p) {
    const ReferenceErrors& e = errs[p];
    const bool sd = rec.sd_step() == sim.step_index() && e.distances;
    const PairSeries& ser = rec.series()[p];
    const char* const* fig = key::kErrorFigures;  // pos_err_max, pos_err_rms, gap_max, gap_mean
    at(sum, key::pair_key(static_cast<int>(p), key::kErrorVsReferenceAlso)) = {
        {"dir", cmp.dir()},
        {"converged", conv ? json(*conv) : json(nullptr)},
        {fig[0], e.pos_err_max},
        {fig[1], e.pos_err_rms},
        {fig[2], sd ? json(e.gap_max) : json(nullptr)},
        {fig[3], sd ? json(e.gap_mean) : json(nullptr)},
        {"touching_nodes", e.touching},
        {"window", {{"pos_err_max", stat_json(ser.also_pos_err_max.over(span))},
                    {"pos_err_rms", stat_json(ser.also_pos_err_rms.over(span))},
                    {"gap_max", stat_json(ser.also_gap_max.over(span))},
                    {"gap_mean", stat_json(ser.also_gap_mean.over(span))}}}};
  }
}

json number_or_null(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

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
  ep << "pair,body,node,first_step,last_step,steps,open,tunnelled\n";
  for (const Episode& e : rec.episodes())
    ep << sim.pairs()[e.pair].label << "," << sim.world().bodies[e.body].name << ","
       << sim.world().bodies[e.body].scene_index(e.node) << "," << e.first
       << "," << e.last << "," << (e.last - e.first + every) << "," << (e.open ? 1 : 0) << ","
       << (e.tunnelled ? 1 : 0) << "\n";
  if (!ep) throw std::runtime_error("cannot write penetration_episodes.csv");
}

}  // namespace harness
