#include "core/effects/loads.hpp"

#include <algorithm>

namespace harness {

Vec3 LoadsEffect::node_force(const LoadNodes& l, int step) {
  const double ramp = l.ramp_steps <= 0 ? 1.0 : std::min(1.0, static_cast<double>(std::max(step, 0)) / l.ramp_steps);
  return (ramp / static_cast<double>(l.nodes.size())) * l.force;
}

void LoadsEffect::add_forces(World& w, const StepContext& s) {
  for (const LoadNodes& l : loads_) {
    const Vec3 f = node_force(l, s.step);
    for (int i : l.nodes) w.f[i] += f;
  }
}

std::unique_ptr<Effect> make_loads_effect(EffectBuild& b) {
  if (b.loads.empty()) return nullptr;
  return std::make_unique<LoadsEffect>(b.loads);
}

}  // namespace harness
