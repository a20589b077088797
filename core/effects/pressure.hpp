// Effect "pressure": internal pressure on a body's closed surface (body key "pressure":
// from, to in Pa, ramped linearly over ramp_steps steps): p times each triangle's area along its
// outward normal, a third to each vertex.
#pragma once

#include "core/effects/effects.hpp"
#include "core/scene/scene.hpp"

#include <utility>

namespace harness {

void add_pressure_forces(const World& w, int body, double p, Points& f);
// Pressure of a ramp at (1-based) step.
double ramp_pressure(const PressureSpec& p, int step);

class PressureEffect final : public Effect {
 public:
  explicit PressureEffect(std::vector<std::pair<int, PressureSpec>> bodies) : bodies_(std::move(bodies)) {}
  const char* name() const override { return "pressure"; }
  EffectCategory category() const override { return EffectCategory::external; }
  void add_forces(World& w, const StepContext& s) override;

 private:
  std::vector<std::pair<int, PressureSpec>> bodies_;  // body index, its ramp
};

std::unique_ptr<Effect> make_pressure_effect(EffectBuild& b);

}  // namespace harness
