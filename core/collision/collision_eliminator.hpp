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
// per contact and per step, along the contact line u (unit vector from h to g), as the force
// that brings the pair's approach to rest within the step:
//   F_c = mu * (s / dt + q)
//   s = max(0, -(v_g - v_h) . u)            approach speed
//   q = max(0, -(f_g/m_g - f_h/m_h) . u)    approach acceleration from the forces so far
// with g the guest node, h the nearest host node (det.nearest_hosts(k = 1)), f what the step
// has already accumulated in w.f (springs, pressure, gravity, ...; contact runs after them)
// and mu = m_g m_h / (m_g + m_h) the reduced mass (a kinematic node counts as infinitely heavy
// and contributes no force or acceleration; velocities of kinematic nodes are their kin_v).
// So F_c exceeds the deformation forces pressing the pair together, and stops the approach
// without overshoot. A larger gain (say 2x the load) was tried first: it feeds back through
// the deformation it causes and diverged in cylinder_press. When g and h coincide, |dv| and
// |da| are used. Non-finite terms are ignored. A resting penetration with no load and no
// motion gets F_c = 0. Returns the largest F_c (0 without contacts).
double auto_contact_forces(const World& w, const CollisionDetector& det,
                           const std::vector<Contact>& contacts, double dt, std::vector<double>& out);

}  // namespace harness
