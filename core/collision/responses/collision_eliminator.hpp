// CollisionEliminator: the paper's interface for eliminating collisions with penalty forces.
// An eliminator decides, per contact, the direction of the push and which host nodes take the
// reaction (the swap point: line.hpp, plane.hpp, chosen by EliminatorKind in make_eliminator);
// the magnitude comes from the pair's force rule (force_rule.hpp), the same for every eliminator. Every contact's forces sum to
// zero (Newton's third law): +F n on the guest node, -w_k F n on host node k, sum w_k = 1.
#pragma once

#include "core/collision/detectors/collision_detector.hpp"

#include <memory>

namespace harness {

// One contact's push: direction n (unit) on the guest node, reactions on up to three host
// nodes with weights summing to one. count == 0: the contact gets no force. For a rule of
// depth (ForceRuleDef::depth: the penalty) the eliminator also says how deep the guest node is below
// the host's surface as it sees it: `depth` (m, negative outside) along the outward `normal`.
struct Push {
  int guest = -1;
  Vec3 n = Vec3::Zero();
  int hosts[3] = {-1, -1, -1};
  double weight[3] = {0.0, 0.0, 0.0};
  int count = 0;
  Vec3 normal = Vec3::Zero();
  double depth = 0.0;
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

// The eliminator of a kind (one line per kind in responses.cpp).
std::unique_ptr<CollisionEliminator> make_eliminator(EliminatorKind kind);

}  // namespace harness
