#include "core/effects/pins.hpp"

namespace harness {

PinsEffect::PinsEffect(World& w, const std::vector<int>& nodes) {
  for (int i : nodes) {
    w.kinematic[i] = Kinematic::pinned;
    w.v[i] = Vec3::Zero();
  }
}

std::unique_ptr<Effect> make_pins_effect(EffectBuild& b) { return std::make_unique<PinsEffect>(b.world, b.pinned_nodes); }

}  // namespace harness
