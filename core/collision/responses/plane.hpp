// The paper's plane rule (directions.hpp): the guest node is pushed along the normal of the plane
// through the three nearest host nodes, each of which takes a third of the reaction.
#pragma once

#include "core/collision/responses/collision_eliminator.hpp"

namespace harness {

class PlaneEliminator final : public CollisionEliminator {
 public:
  const char* name() const override { return "plane"; }
  void pushes(const World& w, const ContactSpec& spec, const CollisionDetector& det,
              const std::vector<Contact>& contacts, std::vector<Push>& out) const override;
};

}  // namespace harness
