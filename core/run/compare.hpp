// Error against a reference solution (`harness run SCENE --compare DIR`; DIR a converged
// reference of `harness reference`, or any finished run of the same scene). Per contact pair,
// over the surface vertices of its two bodies:
//   pos_err_max, pos_err_rms  distance between this run's and the reference's vertex (m);
//   gap_max, gap_mean         over the vertices that touch the other body in the reference
//                             (|signed distance| <= kTouchTolerance there): how much farther from
//                             the other body they are in this run than there, max(0, sd - max(0,
//                             sd_ref)) (m; a gap where the right answer has contact; 0 against
//                             itself). Every touching vertex counts, whatever the others do: a
//                             state with some of them inside and others apart reads both a gap
//                             and a depth;
//   depth_max                 the deepest vertex of this run inside the other body (m): here the
//                             surface vertices; the recorder raises it to the deepest node of
//                             either body (interior nodes too) that the inside test finds inside,
//                             however far it went (recorder.hpp).
// A non-finite position or signed distance on either side is never dropped: the comparison fails
// with ComparisonError naming the body and the node.
// Which reference state a step is compared with: the reference's state at the same step when its
// DIR/trajectory.bin has it (same dt), else its final (settled) state; summary.json "compare"
// says which. The run is judged on the mean and largest figure over its final window
// (run/window.hpp), not on one end-of-run snapshot.
#pragma once

#include "core/run/surfaces.hpp"
#include "core/simulation.hpp"

#include <memory>
#include <optional>
#include <stdexcept>
#include <string>

namespace harness {

constexpr double kTouchTolerance = 1e-4;  // m

struct ReferenceErrors {
  double pos_err_max = 0.0, pos_err_rms = 0.0;
  double gap_max = 0.0, gap_mean = 0.0;
  double depth_max = 0.0;
  int touching = 0;           // vertices that touch in the reference
  bool distances = false;     // both states carry signed distances (gap and depth are known)
};

// A figure of the comparison could not be computed: a non-finite position or signed distance
// (its message names the body and the node, and which side it is on).
struct ComparisonError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class Comparison {
 public:
  // Reads DIR/summary.json and DIR/surfaces.csv (and DIR/trajectory.bin when there is one) and
  // checks that they describe the simulation's bodies: InputError ("--compare DIR: ...") naming
  // the first difference (a body missing or renamed, another surface vertex count, a non-finite
  // position or signed distance of a node).
  // `option`: how the errors name it (--compare, --compare-also).
  Comparison(const std::string& dir, const Simulation& sim, const std::string& option = "--compare");

  const std::string& dir() const { return dir_; }
  bool is_reference() const { return is_reference_; }
  // The reference's own verdict (`converged` of harness reference); nullopt for a plain run.
  std::optional<bool> converged() const { return converged_; }
  // The reference's floor (m: how far its answer may be from the converged one), where its summary
  // records one (`reference.floor`, harness reference); nullopt otherwise.
  std::optional<double> floor() const { return floor_; }
  // The reference state at `step`, when the trajectory has it and the runs share dt.
  const SurfaceState* at_step(int step) const;
  // The state step `step` is compared with: at_step(step), else the final state.
  const SurfaceState& target(int step) const;
  bool has_trajectory() const { return !steps_.empty(); }
  const SurfaceState& final_state() const { return final_; }

  // Errors of `state` against `ref` for the pair of bodies (host, guest). Throws ComparisonError
  // for a non-finite position or signed distance (a body whose distances were not measured at
  // all, every one NaN, leaves gap and depth unknown: `distances` false).
  static ReferenceErrors errors(const SurfaceState& state, const SurfaceState& ref, int host, int guest);

 private:
  std::string dir_;
  bool is_reference_ = false;
  std::optional<bool> converged_;
  std::optional<double> floor_;
  SurfaceState final_;
  std::vector<SurfaceState> steps_;  // trajectory, when the runs share dt
};

}  // namespace harness
