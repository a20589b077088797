#include "core/stability.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace harness {

double critical_dt(const World& w, const Effects& effects, std::vector<Vec3>& rows) {
  const int n = w.num_nodes();
  constexpr double inf = std::numeric_limits<double>::infinity();
  bool any = false;
  for (const auto& e : effects) any = any || e->has_stiffness();
  if (!any) return inf;
  rows.assign(static_cast<std::size_t>(n), Vec3::Zero());
  for (const auto& e : effects) e->add_stiffness_rows(w, rows);
  double lam = 0.0;
  for (int i = 0; i < n; ++i)
    if (w.is_free(i)) lam = std::max(lam, rows[i].maxCoeff() * w.inv_m[i]);
  if (lam <= 0.0) return inf;
  return 2.0 / std::sqrt(lam);
}

StabilityGuard::StabilityGuard(const Scene& sc, const World& w, const Effects& effects)
    : dt_(sc.dt), explicit_(sc.integrator == Integrator::symplectic_euler), substep_(sc.guard == Guard::substep) {
  for (const auto& e : effects) active_ = active_ || e->has_stiffness();
  const double d = critical_dt(w, effects, rows_);
  stats_.dt_crit = stats_.dt_crit_min = dt_crit_last_ = d;
  if (explicit_ && std::isfinite(d) && dt_ > 0.9 * d) {
    if (!substep_) {
      char buf[256];
      std::snprintf(buf, sizeof buf,
                    "dt = %.6g s exceeds 0.9 dt_crit = %.6g s (dt_crit = %.6g s, Gershgorin bound); "
                    "lower dt or set time.guard to \"substep\"",
                    dt_, 0.9 * d, d);
      throw InputError(sc.file + ": time.dt", buf);
    }
    const double ratio = dt_ / (0.9 * d);
    if (ratio > 1e6) throw InputError(sc.file + ": time.dt", "dt needs more than 1e6 substeps");
    stats_.substeps = static_cast<int>(std::ceil(ratio));
  }
  stats_.max_substeps = stats_.substeps;
}

void StabilityGuard::before_step(const World& w, const Effects& effects, int step) {
  if (active_ && step > 1 && ((step - 1) % kEvery == 0 || dt_ / stats_.substeps > 0.45 * dt_crit_last_))
    check(w, effects);
}

void StabilityGuard::check(const World& w, const Effects& effects) {
  const double measured = critical_dt(w, effects, rows_);
  // A stiffening law keeps shrinking dt_crit during the coming step: extrapolate the trend
  // since the last check (geometrically) so that the substeps are sized for the step's end.
  double d = measured;
  if (std::isfinite(dt_crit_last_) && dt_crit_last_ > measured && measured > 0.0)
    d = measured * (measured / dt_crit_last_);
  dt_crit_last_ = measured;
  stats_.dt_crit_min = std::min(stats_.dt_crit_min, d);
  if (!explicit_ || !std::isfinite(d)) return;
  const double ratio = dt_ / (0.9 * d);
  if (substep_) {
    stats_.substeps = std::max(1, static_cast<int>(std::ceil(std::min(ratio, 1e6))));
    stats_.max_substeps = std::max(stats_.max_substeps, stats_.substeps);
  } else if (ratio > 1.0) {
    ++stats_.guard_violations;
  }
}

}  // namespace harness
