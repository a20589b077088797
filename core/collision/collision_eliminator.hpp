// CollisionEliminator: the paper's interface for eliminating collisions with penalty forces.
// An eliminator decides, per contact, the direction of the push and which host nodes take the
// reaction (the swap point: line or plane); the magnitude is the pair's constant F or the
// automatic rule, applied the same way for every eliminator. Every contact's forces sum to
// zero (Newton's third law): +F n on the guest node, -w_k F n on host node k, sum w_k = 1.
#pragma once

#include "core/collision/collision_detector.hpp"

#include <memory>

namespace harness {

// One contact's push: direction n (unit) on the guest node, reactions on up to three host
// nodes with weights summing to one. count == 0: the contact gets no force.
struct Push {
  int guest = -1;
  Vec3 n = Vec3::Zero();
  int hosts[3] = {-1, -1, -1};
  double weight[3] = {0.0, 0.0, 0.0};
  int count = 0;
};

class CollisionEliminator {
 public:
  virtual ~CollisionEliminator() = default;
  virtual const char* name() const = 0;
  // One Push per contact, in order (`out` resized, reused across steps).
  virtual void pushes(const World& w, const ContactSpec& spec, const CollisionDetector& det,
                      const std::vector<Contact>& contacts, std::vector<Push>& out) const = 0;
  // The paper's constant force F for every contact (allocates: tests and tools, not the step).
  void eliminate(World& w, const ContactSpec& spec, const CollisionDetector& det,
                 const std::vector<Contact>& contacts, double force) const;
};

std::unique_ptr<CollisionEliminator> make_eliminator(EliminatorKind kind);

// Adds magnitude[i] * pushes[i] into w.f.
void apply_pushes(World& w, const std::vector<Push>& pushes, const std::vector<double>& magnitude);

// Force magnitudes (N) of `"force": "auto"`, one per push, written into `out` (resized; reuse
// it across steps). The paper tunes one constant F by hand, with the rule that it must beat the
// deformation forces. `auto` applies that rule per contact and per step, along the push
// direction n actually applied: the force that makes the guest node separate from its hosts
// at `separation_speed` (v_sep, m/s) by the end of the step:
//   F = max(0, v_sep - w) / (dt * c)
//   w = (v_g - sum_k w_k v_k) . n + dt (a_g - sum_k w_k a_k) . n   separating speed after the
//       step without contact force (a = f/m from what w.f holds: springs, pressure, gravity,
//       ...; contact runs after them)
//   c = 1/m_g + sum_k w_k^2 n_k / m_k   change of that speed per unit impulse, with n_k the
//       number of this step's pushes that lean on host node k: in a large voxel many guest
//       nodes lean on one host node, and without this their reactions add up n_k times (that
//       diverged with 8 and 16 mm voxels).
// A kinematic node counts as infinitely heavy (1/m = 0, no acceleration, velocity kin_v).
// So F beats the deformation forces that press the pair together and stops the approach, and a
// pair resting in contact is pushed apart slowly. Collision uses v_sep = L / (kSeparationSteps
// dt), L the voxel size (or the host's mean spring length for detectors without a grid). A
// larger gain (2x the load) was tried first: it feeds back through the deformation it causes
// and diverged in cylinder_press. Non-finite terms are ignored. `share` is scratch (one int
// per node, left all zero). Returns the largest F (0 without contacts).
double auto_contact_forces(const World& w, const std::vector<Push>& pushes, double dt,
                           double separation_speed, std::vector<double>& out, std::vector<int>& share);

}  // namespace harness
