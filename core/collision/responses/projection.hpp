// Position-based projection ("eliminator": "projection"): the "restrictions" the paper calls too
// slow. After the position update, every penetrating guest node is moved to the host's surface:
// the contact point and depth as the penalty rule measures them (directions.hpp: an exact
// detector's closest point, else the plane of the three nearest host nodes), the correction
//   lambda = depth / (1/m_g + sum_k w_k^2 / m_k),  dx_g = lambda n / m_g,  dx_k = -w_k lambda n / m_k
// shared with the host nodes by inverse mass (kinematic nodes count as infinitely heavy), so
// the centre of mass does not move; velocities are made consistent (v += dx / h), which is the
// impulse m dx / h: momentum is conserved. One pass over the contacts per substep, in order.
#pragma once

#include "core/collision/responses/collision_eliminator.hpp"

namespace harness {

class ProjectionEliminator final : public CollisionEliminator {
 public:
  const char* name() const override { return "projection"; }
  // The plane rule's pushes with every push's normal, depth and reaction weights.
  void pushes(const World& w, const ContactSpec& spec, const CollisionDetector& det,
              const std::vector<Contact>& contacts, std::vector<Push>& out) const override;
};

// Moves the nodes of every push with positive depth as above, velocities by dx / h; adds the
// equivalent force m dx / h^2 into w.f (what the energy audit books as contact work). Returns the
// largest correction of a guest node, m.
double project_pushes(World& w, const std::vector<Push>& pushes, double h);

}  // namespace harness
