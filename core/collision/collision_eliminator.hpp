// CollisionEliminator: the paper's interface for eliminating collisions with penalty forces.
// Every elimination applies equal and opposite forces (Newton's third law): the net force
// of one contact is zero.
#pragma once

#include "core/collision/collision_detector.hpp"

#include <memory>

namespace harness {

class CollisionEliminator {
 public:
  virtual ~CollisionEliminator() = default;
  virtual const char* name() const = 0;
  // Adds the penalty force of magnitude magnitude[i] (N) for contact i into w.f
  // (magnitude.size() == contacts.size()).
  virtual void eliminate(World& w, const ContactSpec& spec, const CollisionDetector& det,
                         const std::vector<Contact>& contacts,
                         const std::vector<double>& magnitude) = 0;
  // The paper's constant force F for every contact (allocates: tests and tools, not the step).
  void eliminate(World& w, const ContactSpec& spec, const CollisionDetector& det,
                 const std::vector<Contact>& contacts, double force) {
    eliminate(w, spec, det, contacts, std::vector<double>(contacts.size(), force));
  }
};

// The eliminator of that kind: LineEliminator or PlaneEliminator (eliminators.hpp).
std::unique_ptr<CollisionEliminator> make_eliminator(EliminatorKind kind);

// Force magnitudes (N) of `"force": "auto"`, one per contact, written into `out` (resized to
// contacts.size(); reuse it across steps to avoid allocation). The paper tunes one constant F
// by hand, with the rule that it must beat the deformation forces. `auto` applies that rule
// per contact and per step, along the contact line u (unit vector from h to g): the force that
// makes the pair separate at `separation_speed` (v_sep, m/s) by the end of the step:
//   F_c = mu * max(0, v_sep - w) / dt,   w = (v_g - v_h) . u + dt (f_g/m_g - f_h/m_h) . u
// w is the separating speed the pair would have after the step without contact force: the
// force therefore beats the deformation forces that press the pair together (the f term) and
// stops the approach (the v term). g is the guest node, h the nearest host node
// (det.nearest_hosts(k = 1)), f what the step has already accumulated in w.f (springs,
// pressure, gravity, ...; contact runs after them), mu = m_g m_h / (m_g + m_h) the reduced
// mass (a kinematic node counts as infinitely heavy and contributes no acceleration; velocities
// of kinematic nodes are their kin_v). When g and h coincide, w = -(|dv| + dt |da|).
// Collision uses v_sep = L / (200 dt), L the voxel size (or the host's mean spring length for
// detectors without a grid): a pair resting in one voxel is pushed out within about 200 steps,
// so initial overlaps resolve, while the ejection energy 1/2 mu v_sep^2 stays small. With
// v_sep = 0 the rule only stops the approach. A larger gain (2x the load) was tried first: it
// feeds back through the deformation it causes and diverged in cylinder_press. Non-finite
// terms are ignored. Returns the largest F_c (0 without contacts).
double auto_contact_forces(const World& w, const CollisionDetector& det,
                           const std::vector<Contact>& contacts, double dt, double separation_speed,
                           std::vector<double>& out);

}  // namespace harness
