#include "core/effects/drivers.hpp"

namespace harness {

void DriversEffect::begin_step(World& w, const StepContext& s) {
  // Active drivers first (a later driver wins where two overlap); then the nodes no active
  // driver moves any more are released with their last velocity. Releasing inside the loop
  // would let an inactive driver free nodes that another driver is moving.
  for (const DriverNodes& d : drivers_)
    for (int i : d.nodes) driven_now_[i] = 0;
  for (const DriverNodes& d : drivers_) {
    if (!(s.step >= d.from_step && (d.to_step < 0 || s.step <= d.to_step))) continue;
    for (int i : d.nodes) {
      if (w.kinematic[i] == Kinematic::pinned) continue;
      driven_now_[i] = 1;
      w.kinematic[i] = Kinematic::driven;
      w.kin_v[i] = d.velocity;
      w.v[i] = d.velocity;
    }
  }
  for (const DriverNodes& d : drivers_)
    for (int i : d.nodes)
      if (!driven_now_[i] && w.kinematic[i] == Kinematic::driven) {
        w.kinematic[i] = Kinematic::free;  // released: keeps its last velocity
        w.kin_v[i] = Vec3::Zero();
      }
}

std::unique_ptr<Effect> make_drivers_effect(EffectBuild& b) { return std::make_unique<DriversEffect>(b.world, b.drivers); }

}  // namespace harness
