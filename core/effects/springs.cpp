#include "core/effects/springs.hpp"

#include "core/scene/scene.hpp"
#include "core/springs.hpp"

#include <algorithm>

namespace harness {

void SpringsEffect::add_jacobian(const World& w, LinearSystem& sys) const {
  sys.spring_used = true;
  for (std::size_t k = 0; k < w.springs.size(); ++k) {
    const int i = w.springs.ends[k][0], j = w.springs.ends[k][1];
    if (!w.is_free(i) && !w.is_free(j)) continue;
    const Vec3 d = w.x[j] - w.x[i];
    const double l = d.norm();
    if (l <= 0.0) continue;
    const SpringLaw law = w.body_law[w.springs.body[k]].with(w.springs.k[k]);
    double t = 0.0, kt = 0.0;
    spring_tension_tangent(law, w.springs.rest[k], l, t, kt);
    sys.spring_axial[k] = kt;
    sys.spring_transverse[k] = std::max(t / l, 0.0);
  }
}

SpringPassOut SpringsEffect::outputs(World& w, const StepContext& s) const {
  SpringPassOut out;
  out.f = &w.f;
  out.f_spring = s.f_spring;
  out.f_dashpot = dashpots_ ? s.f_dashpot : nullptr;
  out.energy = s.spring_energy;
  out.rows = s.guard_rows;
  return out;
}

void SpringsEffect::add_forces(World& w, const StepContext& s) { spring_pass(gather_, w, true, dashpots_, outputs(w, s)); }

void SpringsEffect::add_forces_shared(World& w, const StepContext& s) {
  spring_pass_shared(gather_, w, true, dashpots_, outputs(w, s));
}

bool SpringsEffect::add_stiffness_rows(const World& w, std::vector<Vec3>& rows) const {
  if (!has_springs_) return false;
  add_spring_stiffness_rows(gather_, w, rows);
  return true;
}

std::unique_ptr<Effect> make_springs_effect(EffectBuild& b) {
  return std::make_unique<SpringsEffect>(b.world, b.scene.has(kDamping));
}

}  // namespace harness
