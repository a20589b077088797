#include "core/effects/pressure.hpp"

#include <algorithm>

namespace harness {

void add_pressure_forces(const World& w, int body, double p, Points& f) {
  const Body& b = w.bodies[body];
  const double s = p / 6.0;  // area vector = cross/2, a third to each vertex
  for (const Tri& t : b.faces) {
    const int i = b.begin + t[0], j = b.begin + t[1], k = b.begin + t[2];
    const Vec3 fn = s * (w.x[j] - w.x[i]).cross(w.x[k] - w.x[i]);
    f[i] += fn;
    f[j] += fn;
    f[k] += fn;
  }
}

double ramp_pressure(const PressureSpec& p, int step) {
  if (p.ramp_steps <= 0 || step >= p.ramp_steps) return p.to;
  const double a = static_cast<double>(std::max(step, 0)) / p.ramp_steps;
  return p.from + (p.to - p.from) * a;
}

void PressureEffect::add_forces(World& w, const StepContext& s) {
  for (const auto& [body, spec] : bodies_) add_pressure_forces(w, body, ramp_pressure(spec, s.step), w.f);
}

std::unique_ptr<Effect> make_pressure_effect(EffectBuild& b) {
  std::vector<std::pair<int, PressureSpec>> bodies;
  for (std::size_t i = 0; i < b.scene.bodies.size(); ++i)
    if (b.scene.bodies[i].pressure.present) bodies.emplace_back(static_cast<int>(i), b.scene.bodies[i].pressure);
  if (bodies.empty()) return nullptr;
  return std::make_unique<PressureEffect>(std::move(bodies));
}

}  // namespace harness
