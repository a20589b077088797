// Effect "contact": every contact pair's Collision (detect, then eliminate with penalty forces),
// after every other force of the step. The pairs themselves belong to the simulation (they are
// measured whether or not contact is simulated); this effect fills in their `collision` and
// their per-step figures (Pair::last).
#pragma once

#include "core/collision/collision.hpp"
#include "core/effects/effects.hpp"

namespace harness {

class ContactEffect final : public Effect {
 public:
  explicit ContactEffect(std::vector<Pair>& pairs) : pairs_(pairs) {}
  const char* name() const override { return "contact"; }
  EffectCategory category() const override { return EffectCategory::contact; }
  void begin_step(World& w, const StepContext& s) override;
  void add_forces(World& w, const StepContext& s) override;
  // One task per pair and direction (Collision::ahead_parts).
  int ahead_tasks() const override;
  void detect_ahead(const World& w, int task) override;
  void ahead_done() override;
  void end_step(World& w, const StepContext& s) override;
  void after_integration(World& w, const StepContext& s) override;
  bool corrects_positions() const override;
  double work(const World& w, const Points& dx) const override;
  // Pairs with the penalty rule have stiffness: k_c n n^T between a guest node and its hosts.
  // Before the first step every guest node counts as in contact (Gershgorin: 2 k_c on its rows);
  // then the last step's pushes do, each host node with its weight.
  bool has_stiffness() const override;
  bool add_stiffness_rows(const World& w, std::vector<Vec3>& rows) const override;
  // The same stiffness for the implicit step: one ContactBlock per push of the last step with a
  // force (effect.hpp, LinearSystem).
  void add_jacobian(const World& w, LinearSystem& sys) const override;

 private:
  std::vector<Pair>& pairs_;
};

std::unique_ptr<Effect> make_contact_effect(EffectBuild& b);

}  // namespace harness
