// The stability guard of the explicit integrator. Symplectic Euler is stable for
// dt < dt_crit = 2 / sqrt(lambda_max(M^-1 K)); lambda_max is bounded by Gershgorin: the largest
// row sum of |K| (from the stiffness the built effects report, effect.hpp) over the node's mass.
// Only effects the scene lists count: a scene without springs is never refused or substepped
// for springs. At build, a dt above 0.9 dt_crit is refused (guard "refuse", InputError) or split
// into substeps (guard "substep"). During the run dt_crit is re-evaluated at the current strain
// every kEvery steps, and every step once dt per substep is within a factor 2 of the limit
// (stiffening laws can halve dt_crit within ten steps).
#pragma once

#include "core/effects/effect.hpp"
#include "core/scene/scene.hpp"

#include <memory>
#include <vector>

namespace harness {

// The largest share of dt_crit an explicit step may take (the guard refuses or substeps above it).
constexpr double kGuardFraction = 0.9;


using Effects = std::vector<std::unique_ptr<Effect>>;

// dt_crit (s) of the effects at the current state; infinity without stiffness. Kinematic nodes
// are skipped (they are not integrated). `rows` is scratch (pass the same vector every time).
double critical_dt(const World& w, const Effects& effects, std::vector<Vec3>& rows);
// The same, and without the contact effect's stiffness (the springs' alone, for the trend).
struct CriticalDt {
  double all, without_contact;
};
// elastic_done: rows already holds the elastic effects' rows (the springs' force pass computed
// them): only the other effects' are added.
CriticalDt critical_dts(const World& w, const Effects& effects, std::vector<Vec3>& rows, bool elastic_done = false);

struct StabilityStats {
  double dt_crit = 0.0;      // s, at rest
  double dt_crit_min = 0.0;  // smallest seen (extrapolated), s
  int substeps = 1;          // explicit substeps per step now
  int max_substeps = 1;
  int guard_violations = 0;  // checks with dt > 0.9 dt_crit under guard "refuse"
};

class StabilityGuard {
 public:
  static constexpr int kEvery = 10;
  // Evaluates dt_crit at rest; throws InputError (time.dt) when the guard refuses dt.
  StabilityGuard(const Scene& scene, const World& w, const Effects& effects);
  // Before step `step` (1-based): re-evaluates dt_crit when due and adapts the substeps.
  void before_step(const World& w, const Effects& effects, int step);
  // The same in two halves, for a step whose springs' force pass computes their rows too (one pass
  // over the springs, not two): due(step) says whether a check is due; rows() is then zeroed and
  // filled by the pass (StepContext::guard_rows), and check_with_rows() adds the other effects'
  // rows and adapts the substeps, before any force that depends on the substep (contact).
  bool due(int step) const;
  std::vector<Vec3>& rows() { return rows_; }
  void check_with_rows(const World& w, const Effects& effects);
  int substeps() const { return stats_.substeps; }
  const StabilityStats& stats() const { return stats_; }

 private:
  void check(const World& w, const Effects& effects);
  void adapt(const CriticalDt& c);

  double dt_;
  bool explicit_, substep_;
  int max_substeps_;  // time.max_substeps: above it the step fails (std::runtime_error)
  bool active_ = false;       // some built effect has stiffness
  double dt_crit_last_ = 0.0;  // at the last check
  double elastic_last_ = 0.0;  // without contact, at the last check
  std::vector<Vec3> rows_;
  StabilityStats stats_;
};

}  // namespace harness
