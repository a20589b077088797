// Error against a reference solution (`harness run SCENE --compare DIR`; DIR a converged
// reference of `harness reference`, or any finished run of the same scene). Per contact pair,
// over the surface vertices of its two bodies:
//   pos_err_max, pos_err_rms  distance between this run's and the reference's vertex (m);
//   gap_max, gap_mean         over the vertices that touch the other body in the reference
//                             (|signed distance| <= kTouchTolerance there): how much farther from
//                             the other body they are in this run than there, max(0, sd - max(0,
//                             sd_ref)) (m; a gap where the right answer has contact; 0 against
//                             itself);
//   depth_max                 the deepest vertex of this run inside the other body (m).
// Settled (final) states are compared at the end; with DIR/trajectory.bin and the same dt, every
// measured step is compared with the reference's state at the same step.
#pragma once

#include "core/run/surfaces.hpp"
#include "core/simulation.hpp"

#include <memory>
#include <optional>
#include <string>

namespace harness {

constexpr double kTouchTolerance = 1e-4;  // m

struct ReferenceErrors {
  double pos_err_max = 0.0, pos_err_rms = 0.0;
  double gap_max = 0.0, gap_mean = 0.0;
  double depth_max = 0.0;
  int touching = 0;  // vertices that touch in the reference
};

class Comparison {
 public:
  // Reads DIR/summary.json and DIR/surfaces.csv (and DIR/trajectory.bin when there is one) and
  // checks that they describe the simulation's bodies: InputError ("--compare DIR: ...") naming
  // the first difference (a body missing or renamed, another surface vertex count).
  Comparison(const std::string& dir, const Simulation& sim);

  const std::string& dir() const { return dir_; }
  bool is_reference() const { return is_reference_; }
  // The reference's own verdict (`converged` of harness reference); nullopt for a plain run.
  std::optional<bool> converged() const { return converged_; }
  // The reference state at `step`, when the trajectory has it and the runs share dt.
  const SurfaceState* at_step(int step) const;
  const SurfaceState& final_state() const { return final_; }

  // Errors of `state` against `ref` for the pair of bodies (host, guest).
  static ReferenceErrors errors(const SurfaceState& state, const SurfaceState& ref, int host, int guest);

 private:
  std::string dir_;
  bool is_reference_ = false;
  std::optional<bool> converged_;
  SurfaceState final_;
  std::vector<SurfaceState> steps_;  // trajectory, when the runs share dt
};

}  // namespace harness
