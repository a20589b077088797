// The distance field's eliminator ("distance_field", with the distance_field detector: the voxel
// contact method of haptics, detectors/distance_field.hpp): each contact is pushed along the
// field's gradient at its node, as deep as the field says, the reaction on the nearest host
// triangle by the barycentric weights of the node's closest point on it. With the penalty rule
// the force is k * depth along the gradient; a constant or automatic force takes the same
// direction.
#pragma once

#include "core/collision/responses/collision_eliminator.hpp"

namespace harness {

class FieldEliminator final : public CollisionEliminator {
 public:
  const char* name() const override { return "distance_field"; }
  void pushes(const World& w, const ContactSpec& spec, const CollisionDetector& det,
              const std::vector<Contact>& contacts, std::vector<Push>& out) const override;
};

}  // namespace harness
