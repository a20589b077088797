// The arithmetic the force rules share (each rule is its own file under core/collision/rules/,
// registered by force_rule.hpp): the penalty's and the automatic force's magnitudes, the contact
// damping variant applied after any rule, and the scatter of magnitudes along the pushes into
// World::f (the direction and the host nodes that take the reaction come from the eliminator,
// collision_eliminator.hpp).
#pragma once

#include "core/collision/responses/collision_eliminator.hpp"

namespace harness {

// The penalty rule: out[i] = k max(0, depth_i), and every push's direction set to its normal
// (resized; reuse it). Returns the largest force (0 without contacts).
double penalty_contact_forces(std::vector<Push>& pushes, double k, std::vector<double>& out);

// The contact damping variant (ContactSpec::damping, not the paper's method): where out[i] > 0,
// out[i] = max(0, out[i] - c v_n), v_n = (v_g - sum_k w_k v_k) . n_i the guest node's speed away
// from its hosts along the push (a kinematic node's velocity is its driver's). It only takes
// energy out: the force falls where the pair separates and rises where it approaches, never
// turning into a pull. Returns the largest magnitude after it (0 without contacts).
double damp_contact_forces(const World& w, const std::vector<Push>& pushes, double c, std::vector<double>& out);

// Adds magnitude[i] * pushes[i] into f (one entry per world node): the guest node gets
// magnitude n, each host node minus its weight times that.
void scatter_pushes(Points& f, const std::vector<Push>& pushes, const std::vector<double>& magnitude);
// scatter_pushes into w.f.
inline void apply_pushes(World& w, const std::vector<Push>& pushes, const std::vector<double>& magnitude) {
  scatter_pushes(w.f, pushes, magnitude);
}

// Force magnitudes (N) of `"force": "auto"`, one per push, written into `out` (resized; reuse
// it across steps). The paper tunes one constant F by hand, with the rule that it must beat the
// deformation forces. `auto` applies that rule per contact and per step, along the push
// direction n actually applied: the force that makes the guest node separate from its hosts
// at `separation_speed` (v_sep, m/s) by the end of the (sub)step of h seconds:
//   F = max(0, v_sep - w) / (h * c)
//   w = (v_g - sum_k w_k v_k) . n + h (a_g - sum_k w_k a_k) . n   separating speed after the
//       step without contact force (a = f/m from what w.f holds: springs, pressure, gravity,
//       ...; contact runs after them)
//   c = 1/m_g + sum_k w_k^2 n_k / m_k   change of that speed per unit impulse, with n_k the
//       number of this step's pushes that lean on host node k: in a large voxel many guest
//       nodes lean on one host node, and their reactions add up n_k times.
// A kinematic node counts as infinitely heavy (1/m = 0, no acceleration, velocity kin_v).
// So F beats the deformation forces that press the pair together and stops the approach, and a
// pair resting in contact is pushed apart slowly. Collision uses v_sep = L / separation_time,
// L the voxel size (or the host's node spacing for detectors without a grid).
// Non-finite terms are ignored. `share` is scratch (one int per node, left all zero). Returns the
// largest F (0 without contacts).
double auto_contact_forces(const World& w, const std::vector<Push>& pushes, double h,
                           double separation_speed, std::vector<double>& out, std::vector<int>& share);

}  // namespace harness
