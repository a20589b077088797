#include "core/run/window.hpp"

#include <algorithm>
#include <climits>
#include <cmath>

namespace harness {

int forcing_end_step(const Scene& sc) {
  int end = 0;
  for (const BodySpec& b : sc.bodies) {
    if (sc.has(kDrivers))
      for (const DriverSpec& d : b.drivers) {
        if (d.velocity.squaredNorm() == 0.0) continue;  // a hold, not a motion
        if (d.to_step < 0) return INT_MAX;
        end = std::max(end, d.to_step);
      }
    if (sc.has(kLoads))
      for (const LoadSpec& l : b.loads) end = std::max(end, l.ramp_steps);
    if (sc.has(kPressure) && b.pressure.present && b.pressure.from != b.pressure.to)
      end = std::max(end, b.pressure.ramp_steps);
  }
  return end;
}

WindowSpan window_span(const Scene& sc, int last_step) {
  WindowSpan w;
  w.to = last_step;
  w.forcing_end = forcing_end_step(sc);
  w.after_forcing = w.forcing_end < last_step;
  const int by_length = last_step - std::max(1, sc.window) + 1;
  w.from = std::max(1, by_length);
  if (w.after_forcing) w.from = std::max(w.from, w.forcing_end + 1);
  return w;
}

WindowStat Series::over(const WindowSpan& w) const {
  WindowStat s;
  double sum = 0.0;
  for (const auto& [step, v] : points_) {
    if (!w.contains(step)) continue;
    if (s.n == 0) s.max = s.min = v;
    s.max = std::max(s.max, v);
    s.min = std::min(s.min, v);
    sum += v;
    ++s.n;
  }
  if (s.n) s.mean = sum / s.n;
  return s;
}

double Series::peak() const {
  double p = std::numeric_limits<double>::quiet_NaN();
  for (const auto& [step, v] : points_) p = std::isnan(p) ? v : std::max(p, v);
  return p;
}

StabilityJudgement judge_stability(const Scene& sc, const std::vector<StepEnergy>& energy, double initial_energy,
                                   bool settled, const StabilityInputs& in) {
  StabilityJudgement j;
  j.inputs = in;
  const int last = static_cast<int>(energy.size());
  j.span = window_span(sc, last);
  if (last == 0) {
    j.verdict = verdict_name(settled ? Verdict::settled : Verdict::steady);
    return j;
  }
  const int from = j.span.from, to = j.span.to;
  Series ke, res;
  for (int s = from; s <= to; ++s) ke.add(s, energy[s - 1].kinetic), res.add(s, energy[s - 1].residual);
  j.kinetic = ke.over(j.span);
  j.residual = res.over(j.span);
  const StepEnergy before = from > 1 ? energy[from - 2] : StepEnergy{};
  const double T = j.span.steps() * sc.dt;
  // The time the energy was put in over: the loading period where the scene is forced and the
  // window starts after it (not the time before the window: a run settled twice as long would read
  // half the input power); the window's own length where nothing forces the scene (energy given at
  // the start: initial velocities); the time before the window for a run still forced.
  double t_in = T;                                 // nothing forces the scene (or no step before the window)
  if (j.span.forcing_end > 0 && from > 1)          // forced
    t_in = j.span.after_forcing && j.span.forcing_end != INT_MAX ? j.span.forcing_end * sc.dt : (from - 1) * sc.dt;
  j.input_period = t_in;
  j.contact_power = (energy[to - 1].work_contact - before.work_contact) / T;
  j.energy_in = initial_energy + std::max(0.0, before.work_external);
  if (j.energy_in > 0.0) {
    j.input_power = j.energy_in / t_in;
  } else {  // nothing put in: the elastic energy held at the window's end, over the window
    j.input_power = energy[to - 1].elastic / T;
  }
  j.ratio = j.input_power > 0.0 ? j.contact_power / j.input_power : (j.contact_power > 0.0 ? INFINITY : 0.0);
  j.net_contact_work = energy[to - 1].work_contact;
  const double scale = std::max(j.energy_in, energy[to - 1].elastic);
  j.energy_scale = scale;
  j.kicked = j.net_contact_work > kKickShare * scale && j.kinetic.mean > kKickShare * scale;
  // Growth: the largest kinetic energy of the window's second half against its first half.
  const int mid = from + (to - from + 1) / 2;
  double first = 0.0, second = 0.0;
  for (int s = from; s < mid; ++s) first = std::max(first, energy[s - 1].kinetic);
  for (int s = mid; s <= to; ++s) second = std::max(second, energy[s - 1].kinetic);
  j.growth = first > 0.0 ? second / first : (second > 0.0 ? INFINITY : 1.0);
  // The class (window.hpp): time scale, stored energy, the contact's input per time scale, growth
  // above its floor, the chatter against its length.
  j.time_scale = std::isfinite(in.time_scale) && in.time_scale > 0.0 ? in.time_scale : T;
  double ke_mean = j.kinetic.n ? j.kinetic.mean : 0.0;
  const double elastic_end = std::isfinite(energy[to - 1].elastic) ? energy[to - 1].elastic : 0.0;
  j.stored_energy = elastic_end + ke_mean;
  const double dw = std::max(0.0, energy[to - 1].work_contact - before.work_contact);
  const double per_scale = dw * j.time_scale / T;
  j.contact_input_share = j.stored_energy > 0.0 ? per_scale / j.stored_energy : (per_scale > 0.0 ? INFINITY : 0.0);
  const double L = in.chatter_length;
  j.growth_floor = std::isfinite(L) ? 0.5 * in.free_mass * (L / j.time_scale) * (L / j.time_scale) : 0.0;
  const double negligible = std::max(j.growth_floor, 1e-9 * std::max(scale, 1e-300));
  if (settled) j.verdict = verdict_name(Verdict::settled);
  else if (!j.span.after_forcing) j.verdict = verdict_name(Verdict::forced);  // still loaded: nothing to judge yet
  else if (j.contact_input_share > kContactInputShare) j.verdict = verdict_name(Verdict::injects);
  else if (j.growth > kGrowthFactor && second > negligible && to - from >= 10) j.verdict = verdict_name(Verdict::grows);
  else if (in.chatter_amplitude > L) j.verdict = verdict_name(Verdict::chatters);
  else j.verdict = verdict_name(Verdict::steady);
  return j;
}

}  // namespace harness
