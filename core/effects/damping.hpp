// Effect "damping": a dashpot along every spring (material.damping, N s/m: force
// c ((v_j - v_i) . d / l^2) d on end i) and mass-proportional damping (material.mass_damping,
// 1/s: force -alpha m v on every node of the body).
#pragma once

#include "core/effects/effects.hpp"
#include "core/spring_forces.hpp"

namespace harness {

class DampingEffect final : public Effect {
 public:
  const char* name() const override { return "damping"; }
  EffectCategory category() const override { return EffectCategory::dissipative; }
  // by_springs: the springs effect is listed and adds the dashpots in its pass; this effect then
  // adds the mass-proportional damping only.
  explicit DampingEffect(bool by_springs) : by_springs_(by_springs) {}
  void add_forces(World& w, const StepContext& s) override;
  void add_jacobian(const World& w, LinearSystem& sys) const override;

 private:
  SpringGather gather_;
  bool by_springs_;
};

std::unique_ptr<Effect> make_damping_effect(EffectBuild& b);

}  // namespace harness
