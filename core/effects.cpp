#include "core/effects.hpp"

#include "core/parallel.hpp"
#include "core/spring_forces.hpp"

namespace harness {

void add_gravity_forces(const World& w, const Vec3& g, Points& f) {
  const int n = w.num_nodes();
#pragma omp parallel for num_threads(threads_for(static_cast<std::size_t>(n))) schedule(static)
  for (int i = 0; i < n; ++i) f[i] += w.m[i] * g;
}

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

namespace {

// The effects keep their gather between steps (built on the first step; rebuilt only if the
// number of nodes or springs changes): spring topology and rest lengths are fixed once a world
// is built (materials are read from the World every step).
class SpringsEffect final : public ForceEffect {
 public:
  const char* name() const override { return "springs"; }
  void apply(World& w, const StepInfo&) override {
    add_spring_forces(gather_, w, w.f);
  }
  double energy(const World& w) const override { return spring_potential(w); }

 private:
  SpringGather gather_;
};

class DampingEffect final : public ForceEffect {
 public:
  const char* name() const override { return "damping"; }
  void apply(World& w, const StepInfo&) override {
    add_damping_forces(gather_, w, w.f);
  }

 private:
  SpringGather gather_;
};

class GravityEffect final : public ForceEffect {
 public:
  explicit GravityEffect(const Vec3& g) : g_(g) {}
  const char* name() const override { return "gravity"; }
  void apply(World& w, const StepInfo&) override { add_gravity_forces(w, g_, w.f); }
  double energy(const World& w) const override {
    double e = 0.0;
    for (int i = 0; i < w.num_nodes(); ++i) e -= w.m[i] * g_.dot(w.x[i]);
    return e;
  }

 private:
  Vec3 g_;
};

class PressureEffect final : public ForceEffect {
 public:
  explicit PressureEffect(std::vector<std::pair<int, PressureSpec>> b) : bodies_(std::move(b)) {}
  const char* name() const override { return "pressure"; }
  void apply(World& w, const StepInfo& s) override {
    for (const auto& [body, spec] : bodies_) add_pressure_forces(w, body, ramp_pressure(spec, s.step), w.f);
  }

 private:
  std::vector<std::pair<int, PressureSpec>> bodies_;
};

}  // namespace

std::unique_ptr<ForceEffect> make_springs_effect() { return std::make_unique<SpringsEffect>(); }
std::unique_ptr<ForceEffect> make_damping_effect() { return std::make_unique<DampingEffect>(); }
std::unique_ptr<ForceEffect> make_gravity_effect(const Vec3& g) { return std::make_unique<GravityEffect>(g); }
std::unique_ptr<ForceEffect> make_pressure_effect(std::vector<std::pair<int, PressureSpec>> bodies) {
  return std::make_unique<PressureEffect>(std::move(bodies));
}

}  // namespace harness
