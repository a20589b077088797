// The final window a run is judged on, and its stability verdict.
//
// Window. A run is judged over its final time.window steps (Scene::window, default 1000), and
// never before every driver that moves its nodes, every load ramp and every pressure ramp has
// finished (forcing_end_step): steps [from, to] with
//   to = the last step, from = max(forcing_end + 1, to - window + 1, 1).
// A run that ends before its forcing does (`--steps` shorter than a driver) is judged over its
// last `window` steps all the same, and says so (after_forcing false). Each figure of the window
// (errors against the reference, depth, tunnelled nodes, kinetic energy, residual) is reported as
// its mean, maximum, minimum and chatter amplitude (maximum minus minimum) over the steps of the
// window on which it was measured (the references' steps, every references.every, and the last).
//
// Stability as a rate. Over the window the contact's mean power is
//   P_contact = (W_contact(to) - W_contact(from - 1)) / T,  T = (to - from + 1) dt,
// (energy audit, energy.hpp: positive when contact injects energy), against the mean power with
// which the scene put its energy in,
//   P_in = (E_initial + W_external(from - 1)) / t_in,
//   t_in = forcing_end dt, the loading period, when the scene is forced and the window follows it;
//          T when nothing forces it (energy given at the start, as initial velocities);
//          (from - 1) dt for a run still forced at its end (not judged: "forced"),
// or, where nothing was put in, the elastic energy at the window's end over T. Their ratio
// rho = P_contact / P_in does not depend on how long the run went on after its forcing: neither
// the window's power nor the loading's does (a cumulative share would: a constant injection crosses
// any share if the run is long enough; and so did P_in over the whole time before the window, which
// read a run settled twice as long as putting its energy in half as fast). The verdict:
//   settled    the run settled (time.settle: the force residual stayed within its tolerance);
//   forced     it ended before its forcing did (after_forcing false): still loaded, not judged;
//   injects    rho > kInjectionRatio: the contact keeps feeding energy into the bodies; or it
//              fed them before the window and they still move with it: its net work over the
//              run and the mean kinetic energy over the window both exceed kKickShare of the
//              energy put in (or of the elastic energy held at the end, if larger) (a body kicked away, which no rate over the window sees: a
//              conservative contact returns what it takes, a trickle below the rate is
//              dissipated). A run that injects warns; with --strict it exits 2 after writing its
//              outputs;
//   grows      the largest kinetic energy of the window's second half is more than
//              kGrowthFactor times that of its first half (and not negligible): it diverges;
//   chatters   none of these: a bounded oscillation, whose amplitude the window figures give.
// Studies call `settled` and `chatters` stable (scripts state their margin around
// kInjectionRatio); a comparison of two runs the rule calls unstable is inconclusive.
#pragma once

#include "core/scene/scene.hpp"

#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace harness {

constexpr double kInjectionRatio = 0.02;  // rho above which contact "injects"
constexpr double kGrowthFactor = 2.0;
constexpr double kKickShare = 0.1;

// The last step at which some driver moves its nodes (a non-zero velocity), a load or a pressure
// is still ramping; 0 when nothing forces the scene; INT_MAX when a driver never stops.
int forcing_end_step(const Scene& sc);

struct WindowSpan {
  int from = 1, to = 0;          // steps, inclusive
  int forcing_end = 0;           // forcing_end_step
  bool after_forcing = true;     // the window starts after the forcing ended
  int steps() const { return to - from + 1; }
  bool contains(int step) const { return step >= from && step <= to; }
};
WindowSpan window_span(const Scene& sc, int last_step);

// Mean, maximum and minimum of a figure over the window's measured steps (n = 0: none).
struct WindowStat {
  int n = 0;
  double mean = std::numeric_limits<double>::quiet_NaN();
  double max = std::numeric_limits<double>::quiet_NaN();
  double min = std::numeric_limits<double>::quiet_NaN();
  double amplitude() const { return max - min; }  // the chatter amplitude
};

// A figure measured on some steps of a run: (step, value) in step order.
class Series {
 public:
  void add(int step, double v) { points_.emplace_back(step, v); }
  WindowStat over(const WindowSpan& w) const;
  bool empty() const { return points_.empty(); }
  std::size_t size() const { return points_.size(); }
  double last() const { return points_.empty() ? std::numeric_limits<double>::quiet_NaN() : points_.back().second; }
  double peak() const;  // the largest value over the whole run (NaN when empty)

 private:
  std::vector<std::pair<int, double>> points_;
};

// What the energy audit says after each step (index step - 1), for the rate over the window.
struct StepEnergy {
  double work_contact = 0.0, work_external = 0.0;  // J, cumulative
  double kinetic = 0.0, elastic = 0.0;             // J
  double residual = 0.0;
};

struct StabilityJudgement {
  std::string verdict;  // settled | forced | chatters | grows | injects
  WindowSpan span;
  double contact_power = 0.0;  // W, mean over the window
  double input_power = 0.0;    // W, P_in
  double input_period = 0.0;   // s, t_in
  double ratio = 0.0;          // rho
  double growth = 0.0;         // largest KE of the second half / of the first half
  double net_contact_work = 0.0;  // J, W_contact at the end
  double energy_in = 0.0;         // J, initial energy and external work up to the window
  double energy_scale = 0.0;      // J, max(energy_in, elastic energy at the end)
  bool kicked = false;            // injects by the net work still held as motion
  WindowStat kinetic, residual;
  bool stable() const { return verdict == "settled" || verdict == "chatters"; }
};

// The verdict of a run of `energy.size()` steps (energy[k] after step k + 1), from its energy
// record, its initial energy and whether it settled.
StabilityJudgement judge_stability(const Scene& sc, const std::vector<StepEnergy>& energy, double initial_energy,
                                   bool settled);

}  // namespace harness
