// CollisionEliminator: the paper's interface for eliminating collisions with penalty forces.
// An eliminator decides, per contact, the direction of the push and which host nodes take the
// reaction (the swap point: line.hpp, plane.hpp, ..., registered below, made by make_eliminator);
// the magnitude comes from the pair's force rule (force_rule.hpp), the same for every eliminator. Every contact's forces sum to
// zero (Newton's third law): +F n on the guest node, -w_k F n on host node k, sum w_k = 1.
#pragma once

#include "core/collision/detectors/collision_detector.hpp"

#include <memory>
#include <string>

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

// The eliminators' registry. An eliminator is its file pair in core/collision/responses/; its
// .cpp defines it with HARNESS_ELIMINATOR(stem) (a line of its own at the start of the line),
// which CMake finds there and calls through a generated list (build/generated/
// eliminator_list.hpp), so the static library's link cannot drop it and adding one touches no
// other hand-written file. The key table (contacts.N.eliminator), the schema and the device's
// refusals read it.
struct EliminatorDef {
  const char* name = "";
  const char* doc = "";  // what it does, for the key's description and docs/scenes.md
  std::unique_ptr<CollisionEliminator> (*make)() = nullptr;
  // Position-based: it moves nodes after the position update (Collision::project) and applies no
  // force, so a force rule or a response of its own has nothing to scale.
  bool projects = false;
  const char* detector = "";  // the one detector it needs ("" any)
  // Its device kernel (core/device/contact_kernels.hpp: kElim*), or -1: `--device` refuses it.
  int device = -1;
};
const std::vector<EliminatorDef>& eliminators();
// The eliminator of that name, or nullptr; eliminator_of throws std::logic_error when unknown.
const EliminatorDef* find_eliminator(const std::string& name);
const EliminatorDef& eliminator_of(const ContactSpec& spec);
// The eliminators as docs/scenes.md lists them ("Eliminators"; `harness rules` prints it).
std::string eliminators_markdown();
// The pair's eliminator, made.
std::unique_ptr<CollisionEliminator> make_eliminator(const std::string& name);

#define HARNESS_ELIMINATOR(stem) EliminatorDef make_eliminator_##stem()

}  // namespace harness
