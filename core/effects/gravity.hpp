// Effect "gravity": m g on every node (scene key "gravity", m/s^2); potential energy -sum m g.x.
#pragma once

#include "core/effects/effects.hpp"

namespace harness {

void add_gravity_forces(const World& w, const Vec3& g, Points& f);

class GravityEffect final : public Effect {
 public:
  explicit GravityEffect(const Vec3& g) : g_(g) {}
  const char* name() const override { return "gravity"; }
  EffectCategory category() const override { return EffectCategory::external; }
  void add_forces(World& w, const StepContext&) override { add_gravity_forces(w, g_, w.f); }
  double energy(const World& w) const override;

 private:
  Vec3 g_;
};

std::unique_ptr<Effect> make_gravity_effect(EffectBuild& b);

}  // namespace harness
