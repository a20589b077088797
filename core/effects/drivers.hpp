// Effect "drivers": the nodes of a driver's selection move with its velocity (Kinematic::driven)
// on steps from_step..to_step (1-based; to_step -1: to the end), and are released afterwards
// with their last velocity. Where drivers overlap, the later one wins; a pin wins over both.
#pragma once

#include "core/effects/effects.hpp"

namespace harness {

class DriversEffect final : public Effect {
 public:
  DriversEffect(const World& w, std::vector<DriverNodes> drivers)
      : drivers_(std::move(drivers)), driven_now_(static_cast<std::size_t>(w.num_nodes()), 0) {}
  const char* name() const override { return "drivers"; }
  void begin_step(World& w, const StepContext& s) override;

 private:
  std::vector<DriverNodes> drivers_;
  std::vector<std::uint8_t> driven_now_;  // scratch of begin_step
};

std::unique_ptr<Effect> make_drivers_effect(EffectBuild& b);

}  // namespace harness
