// The paper's line rule (directions.hpp has the rule and its fallbacks): the guest node is pushed
// along the line from the nearest host node of its voxel, that node takes the reaction.
#pragma once

#include "core/collision/responses/collision_eliminator.hpp"

namespace harness {

class LineEliminator final : public CollisionEliminator {
 public:
  const char* name() const override { return "line"; }
  void pushes(const World& w, const ContactSpec& spec, const CollisionDetector& det,
              const std::vector<Contact>& contacts, std::vector<Push>& out) const override;
};

}  // namespace harness
