// docs/outputs.md, written from the code that writes the outputs: the column table (columns.cpp),
// the stability verdicts (window.hpp) and the summary.json keys below. `harness outputs` prints it;
// tests/core/test_outputs_doc.cpp keeps the committed page equal to it, and tests/cli/test_outputs.sh
// checks that every key a run writes into summary.json is described here.
#include "core/run/columns.hpp"
#include "core/run/outputs_doc.hpp"
#include "core/run/window.hpp"

#include <sstream>

namespace harness {

const std::vector<KeyDoc>& summary_docs() {
  // Top-level keys, then the keys of each pairs[] entry ("pairs[].KEY") and of timing_us
  // ("timing_us.KEY"). `varies`: changes when the same state is reproduced (wall times, provenance).
  static const std::vector<KeyDoc> keys = {
      {"scene", "the scene's name", false},
      {"scene_file", "the scene file the run loaded (empty for a scene given in memory)", false},
      {"status", "`ok`, `error` or `interrupted`", false},
      {"error", "what went wrong (null when status is ok)", false},
      {"steps_run", "steps simulated", false},
      {"finite", "every position and velocity finite at the end", false},
      {"effects", "the effects simulated (the scene's `effects`)", false},
      {"git_commit", "the commit the binary was built from", true},
      {"versions", "compiler, Eigen, FCL, CGAL and other library versions", true},
      {"machine", "the processor model and cores, read from the system", true},
      {"threads", "worker threads the run used", false},
      {"resolved_scene", "the scene with every default written in", false},
      {"state_hash", "hex hash of the final positions and velocities", false},
      {"timing_us", "wall times, us: medians of the step's parts and distributions (below)", true},
      {"budget_us", "the scene's dt in us: a step's real-time budget", false},
      {"realtime_factor_mean", "budget_us over the mean step time", true},
      {"realtime_factor_p99", "budget_us over the 99th percentile step time", true},
      {"stability", "the integrator, dt against dt_crit, the guard and its substeps", false},
      {"window", "the final window the run is judged on: the class's figures (time scale, chatter amplitude and its length, contact input share, growth and its floor), its thresholds, and the earlier rule's rate (recorded, deciding nothing)", false},
      {"stability_verdict", "the run's class (see Stability verdicts); with --ensemble, the class all members share or `flips`", false},
      {"nodes", "nodes of all bodies", false},
      {"node_order", "the memory layout of the nodes (outputs keep the scene's numbering)", false},
      {"springs", "springs of all bodies", false},
      {"bodies", "per body: name, nodes, surface_nodes", false},
      {"kinetic_energy_final", "kinetic energy at the end, J", false},
      {"kinetic_energy_peak", "largest kinetic energy over the run, J", false},
      {"energy", "the energy audit at the end (energies and works, J; balance error)", false},
      {"engine", "the engine that stepped the bodies (`harness` or a peer engine)", false},
      {"settled", "whether the run settled (null without time.settle)", false},
      {"residual", "the force residual at the end", false},
      {"settle_steps", "steps taken to settle", false},
      {"pairs", "one entry per contact pair (below)", false},
      {"compare", "with --compare: the reference's folder, kind and convergence", false},
      {"reference", "`harness reference` only: its levels and convergence", false},
      {"warnings", "the end-of-run warnings", false},
      {"ensemble", "with --ensemble K: the members (node order, jitter seed, class, state hash), the classes counted, each figure's median and range; stability_verdict is then the class all members share, or `flips`", false},
      {"compare_also", "with scripts/runs_compare_also.py: how the second reference's figures were obtained", false},
      {"pairs[].pair", "the pair's label", false},
      {"pairs[].detector", "the detector that drove elimination", false},
      {"pairs[].response", "a contact response of your own that replaced the scene's force rule, by name: \"plugin:NAME\" (contacts.N.response, docs/plugins.md) or \"python:NAME\" (`harness.run(response=...)`); null: the force rule", false},
      {"pairs[].voxel_size_used", "the voxel size used, a power of two, m", false},
      {"pairs[].region_rebuilds", "how often the voxel region was rebuilt", false},
      {"pairs[].contacts_total", "contacts reported over the run", false},
      {"pairs[].true_pen_final", "truly penetrating nodes at the end", false},
      {"pairs[].max_depth_final", "deepest residual penetration at the end, m", false},
      {"pairs[].max_depth_peak", "deepest residual penetration over the run, m", false},
      {"pairs[].recall", "tp / (tp + fn) over the measured steps", false},
      {"pairs[].precision", "tp / (tp + fp) over the measured steps", false},
      {"pairs[].recall_host", "recall of the host nodes (two-sided contact)", false},
      {"pairs[].precision_host", "precision of the host nodes (two-sided contact)", false},
      {"pairs[].scores", "tp, fp, fn (and the host's) summed over the measured steps", false},
      {"pairs[].measured_steps", "steps the references measured", false},
      {"pairs[].tunnelled", "guest nodes through the host at the end", false},
      {"pairs[].tunnelled_host", "host nodes through the guest at the end", false},
      {"pairs[].tunnelled_peak", "most nodes through over the run", false},
      {"pairs[].beyond_band_total", "guest nodes found beyond the detector's band, summed (voxel_exact)", false},
      {"pairs[].beyond_band_peak", "most guest nodes beyond the band in one step (voxel_exact)", false},
      {"pairs[].outside_region", "penetrating guest nodes outside the voxel region at the end", false},
      {"pairs[].outside_region_peak", "most penetrating guest nodes outside the region in one step", false},
      {"pairs[].region_voxels", "voxels of the region: final, peak, mean", false},
      {"pairs[].guest_nodes_inside", "guest nodes inside the region's box, summed over measured steps", false},
      {"pairs[].penetrating_inside", "truly penetrating guest nodes among them", false},
      {"pairs[].window", "the pair's figures over the final window (depth, true penetration, tunnelled)", false},
      {"pairs[].error_vs_reference", "with --compare: position error, gap, depth, tunnelled, window figures, m", false},
      {"pairs[].error_vs_reference_also", "with --compare-also: the same against the second reference", false},
      {"timing_us.step", "median step, us", true},
      {"timing_us.physics", "median step less detection and elimination, us", true},
      {"timing_us.detect", "median detection, us", true},
      {"timing_us.eliminate", "median elimination, us", true},
      {"timing_us.cgal", "median CGAL measurement, us", true},
      {"timing_us.fcl", "median FCL measurement, us", true},
      {"timing_us.outside_step_mean", "mean cost of measurement and outputs outside the step, us", true},
      {"timing_us.outside_step_share", "that cost over the mean step", true},
      {"timing_us.step_mean", "mean step, us", true},
      {"timing_us.step_p99", "99th percentile step, us", true},
      {"timing_us.step_max", "longest step, us", true},
      {"timing_us.steps_timed", "steps timed", false},
      {"timing_us.contact_mean", "mean detection + elimination, us", true},
      {"timing_us.contact_p99", "99th percentile of detection + elimination, us", true},
      {"timing_us.contact_max", "longest detection + elimination, us", true},
      {"timing_us.detect_mean", "mean detection, us", true},
      {"timing_us.detect_p99", "99th percentile detection, us", true},
      {"timing_us.eliminate_mean", "mean elimination, us", true},
      {"timing_us.eliminate_p99", "99th percentile elimination, us", true},
  };
  return keys;
}

namespace {

void table_row(std::ostringstream& o, const std::string& a, const std::string& b) {
  o << "| `" << a << "` | " << b << " |\n";
}

}  // namespace

std::string outputs_markdown() {
  std::ostringstream o;
  o << "# Outputs of `harness run`\n\n"
       "Generated by `build/bin/harness outputs > docs/outputs.md` from the code that writes the outputs\n"
       "(core/run/columns.cpp, core/run/window.hpp, core/run/outputs_doc.cpp); a test fails when this\n"
       "page and the code differ. Do not edit it by hand.\n\n"
       "A run folder holds `steps.csv` (what a reproduced state reproduces), `timing.csv` (wall times),\n"
       "`summary.json`, `surfaces.csv`, `penetration_episodes.csv` where CGAL measured, and `frames/`.\n"
       "A rerun that reproduces `state_hash` changes only `timing.csv` and the summary keys marked\n"
       "*varies* below. Committed copies under results/ may be gzipped (`steps.csv.gz`).\n\n";
  o << "## steps.csv\n\nOne row per step and contact pair (one row per step without pairs). An empty\n"
       "field: not measured on that step, or does not apply.\n\n| column | meaning |\n|---|---|\n";
  for (const Column& c : steps_columns())
    if (!c.timing) table_row(o, c.name, c.doc);
  o << "\n## timing.csv\n\nThe same rows, keyed by";
  for (const char* k : kTimingKeys) o << " `" << k << "`";
  o << "; wall times in microseconds.\n\n| column | meaning |\n|---|---|\n";
  for (const Column& c : steps_columns())
    if (c.timing) table_row(o, c.name, c.doc);
  o << "\n## Stability verdicts\n\n`summary.json` `stability_verdict` is one of:\n\n| verdict | meaning |\n|---|---|\n";
  for (const VerdictDoc& v : kStabilityVerdicts) table_row(o, v.name, v.doc);
  // The thresholds in one table: summary.json records them (window.thresholds) and the result
  // scripts read them from here (scripts/harness_results/judge/measure.py) instead of copying.
  o << "\n## Stability thresholds\n\n| threshold | value | meaning |\n|---|---|---|\n";
  for (const ThresholdDoc& t : kStabilityThresholds) {
    std::ostringstream v;
    v << t.value;
    o << "| `" << t.name << "` | " << v.str() << " | " << t.doc << " |\n";
  }
  o << "\n## summary.json\n\n| key | meaning | varies |\n|---|---|---|\n";
  for (const KeyDoc& k : summary_docs())
    o << "| `" << k.key << "` | " << k.doc << " | " << (k.varies ? "yes" : "") << " |\n";
  return o.str();
}

}  // namespace harness
