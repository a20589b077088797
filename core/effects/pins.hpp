// Effect "pins": the nodes of each body's "pins" selections are held fixed (Kinematic::pinned,
// velocity zero) for the whole run; a pin wins over a driver.
#pragma once

#include "core/effects/effects.hpp"

namespace harness {

class PinsEffect final : public Effect {
 public:
  PinsEffect(World& w, const std::vector<int>& nodes);
  const char* name() const override { return "pins"; }
};

std::unique_ptr<Effect> make_pins_effect(EffectBuild& b);

}  // namespace harness
