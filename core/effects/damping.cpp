#include "core/effects/damping.hpp"

#include "core/scene/scene.hpp"

namespace harness {

void DampingEffect::add_jacobian(const World& w, LinearSystem& sys) const {
  sys.spring_used = true;
  for (std::size_t k = 0; k < w.springs.size(); ++k) sys.spring_dashpot[k] += w.bodies[w.springs.body[k]].material.damping;
  for (const Body& b : w.bodies)
    for (int i = b.begin; i < b.end; ++i) sys.node_damping[i] += b.material.mass_damping;
}

void DampingEffect::add_forces(World& w, const StepContext& s) {
  if (!by_springs_) {
    SpringPassOut out;
    out.f = &w.f;
    out.f_dashpot = s.f_dashpot;
    spring_pass(gather_, w, false, true, out);
  }
  add_mass_damping(w, w.f);
}

std::unique_ptr<Effect> make_damping_effect(EffectBuild& b) {
  return std::make_unique<DampingEffect>(b.scene.has(kSprings));
}

}  // namespace harness
