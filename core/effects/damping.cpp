#include "core/effects/damping.hpp"

namespace harness {

void DampingEffect::add_jacobian(const World& w, LinearSystem& sys) const {
  sys.spring_used = true;
  for (std::size_t k = 0; k < w.springs.size(); ++k) sys.spring_dashpot[k] += w.bodies[w.springs.body[k]].material.damping;
  for (const Body& b : w.bodies)
    for (int i = b.begin; i < b.end; ++i) sys.node_damping[i] += b.material.mass_damping;
}

std::unique_ptr<Effect> make_damping_effect(EffectBuild&) { return std::make_unique<DampingEffect>(); }

}  // namespace harness
