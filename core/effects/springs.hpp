// Effect "springs": every body's springs with its material's law (springs.hpp), evaluated by the
// kernels of spring_forces.hpp; elastic energy; tangent stiffness for the implicit integrator
// and the stability guard.
#pragma once

#include "core/effects/effects.hpp"
#include "core/spring_forces.hpp"

namespace harness {

class SpringsEffect final : public Effect {
 public:
  // dashpots: the damping effect is listed too; then this pass adds the dashpots (one pass over
  // the springs) and the damping effect only the mass-proportional damping.
  SpringsEffect(const World& w, bool dashpots) : has_springs_(w.springs.size() > 0), dashpots_(dashpots) {}
  const char* name() const override { return "springs"; }
  EffectCategory category() const override { return EffectCategory::elastic; }
  void add_forces(World& w, const StepContext& s) override;
  bool shareable(const World& w) override { return spring_pass_shareable(gather_, w); }
  void add_forces_shared(World& w, const StepContext& s) override;
  // K_k = k_t u u^T + max(T / l, 0) (I - u u^T): the compressive geometric term is dropped so
  // that the implicit system stays symmetric positive definite.
  void add_jacobian(const World& w, LinearSystem& sys) const override;
  bool add_stiffness_rows(const World& w, std::vector<Vec3>& rows) const override;
  bool has_stiffness() const override { return has_springs_; }
  double energy(const World& w) const override { return spring_potential(gather_, w, energy_); }

 private:
  SpringPassOut outputs(World& w, const StepContext& s) const;
  mutable SpringGather gather_;  // kept between steps (spring topology is fixed once built)
  mutable std::vector<double> energy_;  // energy(): the node energies, sized once
  bool has_springs_;
  bool dashpots_;
};

std::unique_ptr<Effect> make_springs_effect(EffectBuild& b);

}  // namespace harness
