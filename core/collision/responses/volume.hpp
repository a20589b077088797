// Restriction with a practical bound ("eliminator": "volume"): the restriction the paper calls too
// slow, with its bound computed the way a practitioner computes it. After the position update,
// the volume V the two bodies share and its gradient with respect to their surface vertices come
// from layered depth images (intersection_volume.hpp; Faure et al. 2008); one Newton step on the
// constraint V = 0 (Allard et al. 2010's volume contact constraint) moves the surface vertices of
// both bodies:
//   dx_i = -V inv_i g_i / sum_j inv_j |g_j|^2,   g_i = dV/dx_i,  inv_i = 1/m_i (0: kinematic node),
// so the step is mass-weighted and, the gradient summing to zero over both bodies, the centre of
// mass does not move; velocities are made consistent (v += dx / h): momentum is conserved. The
// interior nodes follow through their springs. One step per substep: a linearisation, so V is
// reduced, not zeroed, when the gradient changes within the step.
#pragma once

#include "core/collision/responses/collision_eliminator.hpp"

#include <utility>
#include <vector>

namespace harness {

class VolumeEliminator final : public CollisionEliminator {
 public:
  const char* name() const override { return "volume"; }
  // No per-contact push: the volume's gradient moves the surfaces (restrict_volume).
  void pushes(const World& w, const ContactSpec& spec, const CollisionDetector& det,
              const std::vector<Contact>& contacts, std::vector<Push>& out) const override;
};

// What one restriction did.
struct VolumeStep {
  double volume = 0.0;  // the shared volume before the step, m^3 (the bound)
  double pixel = 0.0;   // the images' pixel edge used, m
  std::vector<std::pair<int, Vec3>> moves;  // (global node, dx) of every node moved
};

// The pixel edge for a pair: `requested` when positive, else half the smaller of the two bodies'
// mean surface edges at rest (the pair's Collision asks once, when it is made).
double volume_pixel(const World& w, int host, int guest, double requested);

// The Newton step above for bodies host and guest, in a (sub)step of h seconds: moves positions
// and velocities and adds the equivalent forces m dx / h^2 into w.f (what the energy audit books as
// contact work). Returns the largest move, m; `out` says what it did. `invert`: every move the
// wrong way (ContactSpec::invert_push: a broken method for the tests).
double restrict_volume(World& w, int host, int guest, double pixel, double h, VolumeStep& out, bool invert = false);

}  // namespace harness
