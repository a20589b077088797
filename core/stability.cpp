#include "core/stability.hpp"

#include <stdexcept>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace harness {

namespace {

// 2 / sqrt(largest row sum over mass) of the free nodes; infinity without stiffness.
double dt_of_rows(const World& w, const std::vector<Vec3>& rows) {
  double lam = 0.0;
  for (int i = 0; i < w.num_nodes(); ++i)
    if (w.is_free(i)) lam = std::max(lam, rows[i].maxCoeff() * w.inv_m[i]);
  return lam > 0.0 ? 2.0 / std::sqrt(lam) : std::numeric_limits<double>::infinity();
}

}  // namespace

CriticalDt critical_dts(const World& w, const Effects& effects, std::vector<Vec3>& rows, bool elastic_done) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  CriticalDt out{inf, inf};
  bool any = false;
  for (const auto& e : effects) any = any || e->has_stiffness();
  if (!any) return out;
  if (!elastic_done) rows.assign(static_cast<std::size_t>(w.num_nodes()), Vec3::Zero());
  bool contact = false;
  for (const auto& e : effects) {
    if (e->category() == EffectCategory::contact) contact = contact || e->has_stiffness();
    else if (!(elastic_done && e->category() == EffectCategory::elastic)) e->add_stiffness_rows(w, rows);
  }
  out.without_contact = dt_of_rows(w, rows);
  if (!contact) return out.all = out.without_contact, out;
  for (const auto& e : effects)
    if (e->category() == EffectCategory::contact) e->add_stiffness_rows(w, rows);
  out.all = dt_of_rows(w, rows);
  return out;
}

double critical_dt(const World& w, const Effects& effects, std::vector<Vec3>& rows) {
  return critical_dts(w, effects, rows).all;
}

StabilityGuard::StabilityGuard(const Scene& sc, const World& w, const Effects& effects)
    : dt_(sc.dt), explicit_(sc.integrator == Integrator::symplectic_euler), substep_(sc.guard == Guard::substep),
      max_substeps_(sc.max_substeps) {
  for (const auto& e : effects) active_ = active_ || e->has_stiffness();
  const CriticalDt c = critical_dts(w, effects, rows_);
  const double d = c.all;
  stats_.dt_crit = stats_.dt_crit_min = dt_crit_last_ = d;
  elastic_last_ = c.without_contact;
  if (explicit_ && std::isfinite(d) && dt_ > kGuardFraction * d) {
    if (!substep_) {
      char buf[256];
      std::snprintf(buf, sizeof buf,
                    "dt = %.6g s exceeds %g dt_crit = %.6g s (dt_crit = %.6g s, Gershgorin bound); "
                    "lower dt or set time.guard to \"substep\"",
                    dt_, kGuardFraction, kGuardFraction * d, d);
      throw InputError(sc.file + ": time.dt", buf);
    }
    const double ratio = dt_ / (kGuardFraction * d);
    if (ratio > max_substeps_) {
      char buf[200];
      std::snprintf(buf, sizeof buf, "dt needs %.3g substeps at rest, above time.max_substeps = %d (lower dt, or raise the cap)",
                    std::ceil(ratio), max_substeps_);
      throw InputError(sc.file + ": time.max_substeps", buf);
    }
    stats_.substeps = static_cast<int>(std::ceil(ratio));
  }
  stats_.max_substeps = stats_.substeps;
}

bool StabilityGuard::due(int step) const {
  return active_ && step > 1 && ((step - 1) % kEvery == 0 || dt_ / stats_.substeps > 0.45 * dt_crit_last_);
}

void StabilityGuard::before_step(const World& w, const Effects& effects, int step) {
  if (due(step)) check(w, effects);
}

void StabilityGuard::check(const World& w, const Effects& effects) { adapt(critical_dts(w, effects, rows_)); }

void StabilityGuard::check_with_rows(const World& w, const Effects& effects) {
  adapt(critical_dts(w, effects, rows_, /*elastic_done=*/true));
}

void StabilityGuard::adapt(const CriticalDt& c) {
  const double measured = c.all;
  // A stiffening law keeps shrinking dt_crit during the coming step: extrapolate the springs'
  // trend since the last check (geometrically) so that the substeps are sized for the step's
  // end. Only the springs': contact stiffness comes and goes with the contacts, by jumps that are
  // no trend (extrapolated, a contact that appeared between two checks read as a collapse of
  // dt_crit, 4.7 times below anything measured, in sphere_collision's reference).
  double d = measured;
  const double el = c.without_contact;
  if (std::isfinite(elastic_last_) && elastic_last_ > el && el > 0.0) d = measured * (el / elastic_last_);
  elastic_last_ = el;
  dt_crit_last_ = measured;
  stats_.dt_crit_min = std::min(stats_.dt_crit_min, d);
  if (!explicit_ || !std::isfinite(d)) return;
  const double ratio = dt_ / (kGuardFraction * d);
  if (substep_) {
    if (!(ratio <= max_substeps_)) {  // NaN too
      char buf[240];
      std::snprintf(buf, sizeof buf,
                    "time.max_substeps: the step needs %.3g substeps (dt_crit fell to %.3g s), above the cap of %d: "
                    "the state stiffened far beyond the scene's (a blow-up, or a contact far stiffer than its bodies)",
                    std::ceil(ratio), d, max_substeps_);
      throw std::runtime_error(buf);
    }
    stats_.substeps = std::max(1, static_cast<int>(std::ceil(ratio)));
    stats_.max_substeps = std::max(stats_.max_substeps, stats_.substeps);
  } else if (ratio > 1.0) {
    ++stats_.guard_violations;
  }
}

}  // namespace harness
