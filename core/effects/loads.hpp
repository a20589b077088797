// Effect "loads": per body, forces applied to selections of nodes (body key "loads"): each
// load's total force (N) is shared equally among its nodes and ramped linearly from zero over
// ramp_steps steps (0: applied in full from the first step).
#pragma once

#include "core/effects/effects.hpp"

namespace harness {

class LoadsEffect final : public Effect {
 public:
  explicit LoadsEffect(std::vector<LoadNodes> loads) : loads_(std::move(loads)) {}
  const char* name() const override { return "loads"; }
  EffectCategory category() const override { return EffectCategory::external; }
  void add_forces(World& w, const StepContext& s) override;
  // The force on each node of load l at (1-based) step `step`.
  static Vec3 node_force(const LoadNodes& l, int step);

 private:
  std::vector<LoadNodes> loads_;
};

std::unique_ptr<Effect> make_loads_effect(EffectBuild& b);

}  // namespace harness
