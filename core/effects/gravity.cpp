#include "core/effects/gravity.hpp"

#include "core/parallel.hpp"
#include "core/scene/scene.hpp"

namespace harness {

void add_gravity_forces(const World& w, const Vec3& g, Points& f) {
  const int n = w.num_nodes();
  const int T = threads_for(static_cast<std::size_t>(n));
#pragma omp parallel for num_threads(T) if(T > 1) schedule(static)
  for (int i = 0; i < n; ++i) f[i] += w.m[i] * g;
}

double GravityEffect::energy(const World& w) const {
  double e = 0.0;
  for (int i = 0; i < w.num_nodes(); ++i) e -= w.m[i] * g_.dot(w.x[i]);
  return e;
}

std::unique_ptr<Effect> make_gravity_effect(EffectBuild& b) { return std::make_unique<GravityEffect>(b.scene.gravity); }

}  // namespace harness
