// The record of a run: the exact references measured on their steps (core/measure.hpp), and
// everything accumulated over the run that summary.json and the test runners read: per pair
// totals, penetration episodes, timings, the kinetic-energy peak. `harness run` (run_scene.cpp) and
// the scene-level tests (tests/reference/scene_runner.hpp) both record through it.
#pragma once

#include "core/measure.hpp"
#include "core/run/compare.hpp"
#include "core/run/window.hpp"
#include "core/simulation.hpp"

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace harness {

// Running totals of one pair over the run.
struct PairTotals {
  long long contacts_total = 0;
  long long tp = 0, fp = 0, fn = 0;                 // guest nodes, over the measured steps
  long long tp_host = 0, fp_host = 0, fn_host = 0;  // host nodes
  bool measured = false;  // CGAL measured at least once
  int true_pen_final = 0;  // at the last measured step, guest + host
  double max_depth_final = 0.0, max_depth_peak = 0.0;
  int tunnelled_guest_peak = 0, tunnelled_host_peak = 0;  // over the measured steps
  // Contacts found beyond the detector's guaranteed band (PairStep::beyond_band): summed over
  // the steps and the largest of one step; has_band: the detector has a band.
  bool has_band = false;
  long long beyond_band_total = 0;
  int beyond_band_peak = 0;
  // Truly penetrating guest nodes outside the detector's grid region (undetectable by it), at
  // the last measured step and the most at one; has_region: the detector has a region.
  bool has_region = false;
  int outside_region_final = 0, outside_region_peak = 0;
  // The grid's region in voxels on the measured steps (its size: it moves with the host, and grows
  // when the host outgrows it): the last, the largest and the sum (mean = sum / samples).
  long long region_voxels_final = 0, region_voxels_peak = 0, region_samples = 0;
  double region_voxels_sum = 0.0;
  // Guest nodes inside the region's box, and truly penetrating ones among them, summed over the
  // same steps: the precision of a detector that flags every guest node in its region.
  long long region_guest_sum = 0, region_pen_sum = 0;
};

// Guest nodes that have passed through the host, and host nodes through the guest, at the last
// CGAL measurement (Measurement::tunnelled_guest / tunnelled_host: entered through one face, left
// through one turned away from it); measured false when the run has no CGAL reference.
struct TunnelCount {
  int guest = 0, host = 0;
  bool measured = false;
};

// One pair's figures over the run, one value per measured step (run/window.hpp).
struct PairSeries {
  Series pos_err_max, pos_err_rms, gap_max, gap_mean;  // against the compared reference, m
  Series depth_max;                                     // deepest node of either body, m (CGAL)
  Series true_pen;                                      // truly penetrating nodes, guest + host
  Series tunnelled;                                     // guest + host
  Series true_pen_guest;                                // truly penetrating guest nodes
  Series outside_region;  // truly penetrating guest nodes outside the detector's grid region
  // Against the second reference (--compare-also), m: the same figures as the first's.
  Series also_pos_err_max, also_pos_err_rms, also_gap_max, also_gap_mean;
};

// One episode of true penetration: a node found penetrating on consecutive measured steps.
// `tunnelled`: it ended on the far side of the other body (the node's passage parity differs
// from the episode's start): not eliminated but gone through, a failure like an open one. A node
// that passes through between two measured steps without being found inside at either makes an
// episode of its own, of no measured length, tunnelled.
struct Episode {
  int pair, body, node, first, last;
  bool open;  // still penetrating when the run ended (censored)
  bool tunnelled = false;
};

// Per-step wall times (microseconds) over the run, for medians.
struct RunTimings {
  std::vector<double> step, physics, detect, eliminate, cgal, fcl;
  // Per step, what the run spends outside the step: the recorder (references, series, episodes),
  // steps.csv, frames, trajectory, progress.
  std::vector<double> outside;
};

struct RecorderOptions {
  MeasurerFactory measurer;  // empty: no references in this program
  const Comparison* compare = nullptr;  // the reference solution to measure the error against
  // A second reference measured beside it on the same steps (--compare-also: the reference of the
  // other kind, one way against both ways); its figures go to PairSeries::also_*.
  const Comparison* compare_also = nullptr;
};

// A pair's figures of one measured step beyond the references' own (CGAL signed distances).
struct PairStepFigures {
  bool force_dist = false;  // some node received a contact force
  double force_dist_max = 0.0, force_dist_mean = 0.0;  // signed distance of those nodes, m
  bool vs_reference = false;  // compared with the reference (its state at this step, or its final one)
  ReferenceErrors errors;     // depth_max: the deepest node of either body (CGAL), all nodes
  bool vs_also = false;       // compared with the second reference too (--compare-also)
  ReferenceErrors also_errors;  // against it (depth_max not set: it does not depend on the reference)
  TunnelCount tunnelled;
};

// The stored (elastic, potential) energies are evaluated on the steps a run measures
// (references.every) and the last, or every kEnergyEvery steps and the last without references:
// the springs' energy costs a pass over the springs (energy_audit.hpp); steps.csv leaves those
// columns empty on the other rows. Works, kinetic energy and residual: every step.
constexpr int kEnergyEvery = 10;

class Recorder {
 public:
  // Makes one measurer per pair when the scene asks for references. Throws InputError
  // (references.solvers) when it asks for them and the program has none.
  Recorder(const Simulation& sim, const RecorderOptions& options);

  // After each completed step: measures when due (every references.every steps, and the last
  // step of the run: `last`) and accumulates.
  void record(const Simulation& sim, bool last = false);

  // This step's measurement of pair p, or null when the references did not run.
  const Measurement* measurement(std::size_t p) const { return measured_now_ ? &meas_[p] : nullptr; }
  // Truly penetrating nodes of a body (body-local flags) when `step` is the last measured step
  // with CGAL, else null (frames carry them only on measured steps).
  const std::vector<std::uint8_t>* penetration(int body, int step) const;
  // This step's figures of pair p beyond the references' (null when not measured).
  const PairStepFigures* figures(std::size_t p) const { return measured_now_ ? &figures_[p] : nullptr; }
  // Per body, per surface vertex: signed distance to its contact partner at the last measured
  // step (empty vectors before any, or without CGAL).
  const std::vector<std::vector<double>>& signed_distance() const { return sd_; }
  int sd_step() const { return sd_step_; }
  // The final state against the compared reference, per pair (after the last step); depth_max
  // the deepest node of either body at the last measured step when it is the last step.
  std::vector<ReferenceErrors> final_errors(const Simulation& sim) const;
  // The same against the second reference (--compare-also); empty without one.
  std::vector<ReferenceErrors> final_errors_also(const Simulation& sim) const;
  // Per pair, its figures at every measured step (window statistics, peaks).
  const std::vector<PairSeries>& series() const { return series_; }
  // The run's stability verdict over its final window (run/window.hpp).
  StabilityJudgement judge(const Simulation& sim, bool settled) const;
  // What the class reads beyond the energy record: the nodes' chatter over the window, its stated
  // length and the time scale (window.hpp).
  StabilityInputs stability_inputs(const Simulation& sim) const;
  const std::vector<PairTotals>& totals() const { return totals_; }
  const std::vector<Episode>& episodes() const { return episodes_; }
  const RunTimings& timings() const { return timings_; }
  // The time the run loop spent outside the step after it (measurement and outputs), µs.
  void note_outside_us(double us) { timings_.outside.push_back(us); }
  double kinetic_energy() const { return ke_; }
  double kinetic_energy_peak() const { return ke_peak_; }
  double potential_energy() const { return pe_; }
  int energy_every() const { return energy_every_; }  // the stored energies every this many steps
  // Nodes that have passed through the other body, at the last CGAL measurement.
  int tunnelled(std::size_t p) const { return tunnel_count(p).guest; }
  TunnelCount tunnel_count(std::size_t p) const;
  bool references() const { return !measurers_.empty(); }

 private:
  void pair_figures(const Simulation& sim);
  void track(std::size_t p, int role, const std::vector<std::uint8_t>& flags, const std::vector<std::uint8_t>* through,
             int step, const Simulation& sim);

  RecorderOptions opt_;
  std::vector<std::unique_ptr<Measurer>> measurers_;
  std::vector<Measurement> meas_;
  std::vector<PairStepFigures> figures_;
  std::vector<std::vector<double>> sd_;
  // The reference's signed distances of a body laid out in another order (Body::scene_node), put
  // in the world's order for the measurer (the reference lists them in the scene's numbering).
  std::vector<std::vector<double>> ref_sd_world_;
  // With a second reference: per body, the signed distance of the two references nearer to
  // contact (smaller magnitude), so that the vertices either one has touching are measured exactly.
  std::vector<std::vector<double>> ref_sd_both_;
  std::vector<ReferenceErrors> final_errors_vs(const Simulation& sim, const Comparison& cmp) const;
  int sd_step_ = -1;
  bool measured_now_ = false;
  std::vector<PairTotals> totals_;
  std::vector<Episode> episodes_;
  std::vector<std::vector<int>> open_;  // per pair and role (guest, host): open episode per node or -1
  // Per pair and role: each node's passage parity at the last measured step, and at its open
  // episode's start.
  std::vector<std::vector<std::uint8_t>> through_last_, through_start_;
  std::vector<std::vector<std::uint8_t>> pen_flags_;  // per body
  int pen_step_ = -1;
  RunTimings timings_;
  double ke_ = 0.0, ke_peak_ = 0.0, pe_ = 0.0;
  int energy_every_ = 1;  // the stored energies every this many steps (and the last)
  std::vector<PairSeries> series_;
  std::vector<StepEnergy> energy_;  // after every step
  double initial_energy_ = 0.0;
  // Each free node's motion from motion_from_ on (the final window the run will have if it does
  // not settle first): per coordinate sum, min and max of its position over motion_n_ steps.
  int motion_from_ = 0;
  int motion_n_ = 0;
  std::vector<Vec3> motion_sum_, motion_min_, motion_max_;
  double time_scale_ = 0.0, free_mass_ = 0.0, edge_length_ = 0.0;
};


}  // namespace harness
