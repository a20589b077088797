#include "core/effects/effects.hpp"

#include "core/effects/contact.hpp"
#include "core/effects/damping.hpp"
#include "core/effects/drivers.hpp"
#include "core/effects/gravity.hpp"
#include "core/effects/loads.hpp"
#include "core/effects/pins.hpp"
#include "core/effects/pressure.hpp"
#include "core/effects/springs.hpp"
#include "core/effects/bulk.hpp"
#include "core/scene/scene.hpp"

namespace harness {

const std::vector<EffectEntry>& effect_table() {
  static const std::vector<EffectEntry> table = {
      {kSprings, effect_name(kSprings), make_springs_effect},
      {kBulk, effect_name(kBulk), make_bulk_effect},
      {kDamping, effect_name(kDamping), make_damping_effect},
      {kGravity, effect_name(kGravity), make_gravity_effect},
      {kPins, effect_name(kPins), make_pins_effect},
      {kDrivers, effect_name(kDrivers), make_drivers_effect},
      {kPressure, effect_name(kPressure), make_pressure_effect},
      {kLoads, effect_name(kLoads), make_loads_effect},
      {kContact, effect_name(kContact), make_contact_effect},
  };
  return table;
}

std::vector<std::unique_ptr<Effect>> make_effects(EffectBuild& b) {
  std::vector<std::unique_ptr<Effect>> out;
  for (const EffectEntry& e : effect_table())
    if (b.scene.effects & e.flag)
      if (auto made = e.make(b)) out.push_back(std::move(made));
  return out;
}

}  // namespace harness
