// Force effects: each is a module built at load only when the scene lists it, then
// evaluated once per step (free functions over the World's arrays do the work; the small
// classes only hold what each effect needs between steps).
#pragma once

#include "core/scene.hpp"
#include "core/spring_forces.hpp"
#include "core/world.hpp"

#include <memory>
#include <vector>

namespace harness {

struct StepInfo {
  int step = 0;        // 1-based number of the step being taken
  double dt = 0.0;     // s
};

class ForceEffect {
 public:
  virtual ~ForceEffect() = default;
  virtual const char* name() const = 0;
  // Adds this effect's forces into w.f.
  virtual void apply(World& w, const StepInfo& s) = 0;
  // Potential energy (J) of conservative effects, for energy balances; 0 otherwise.
  virtual double energy(const World&) const { return 0.0; }
};

// Free functions (also used by tests and benchmarks); the spring and dashpot forces are in
// core/spring_forces.hpp.
void add_gravity_forces(const World& w, const Vec3& g, Points& f);
// Internal pressure p (Pa) on a body's closed surface: p times each triangle's area along its
// outward normal, a third to each vertex.
void add_pressure_forces(const World& w, int body, double p, Points& f);
// Pressure of a ramp at (1-based) step.
double ramp_pressure(const PressureSpec& p, int step);

std::unique_ptr<ForceEffect> make_springs_effect();
std::unique_ptr<ForceEffect> make_damping_effect();
std::unique_ptr<ForceEffect> make_gravity_effect(const Vec3& g);
std::unique_ptr<ForceEffect> make_pressure_effect(std::vector<std::pair<int, PressureSpec>> bodies);

}  // namespace harness
