// The energy audit of a run: what is booked and why (energy_audit.hpp books it). Every effect that
// adds forces belongs to one category (Effect::category()); per substep the force pass keeps the
// forces the audit needs apart (the external effects' in their own array, the springs' and the
// dashpots' as side outputs of their pass), so auditing never changes the state's bits.
//
// Symplectic Euler is leapfrog with staggered velocities: v_{n+1/2} = v_{n-1/2} + h F(x_n) / m,
// x_{n+1} = x_n + h v_{n+1/2}. Its energy in the usual form oscillates by about h omega / 2 of
// the energy of every mode omega, but the staggered energy
//   E*_n = sum 1/2 m v_{n-1/2} . v_{n+1/2} + U(x_n)
// changes exactly by the trapezoidal work of the other forces,
//   E*_{n+1} - E*_n = sum_c W_c,   W_c = 1/2 (f_c(x_n) + f_c(x_{n+1})) . (x_{n+1} - x_n),
// when the springs are linear (for nonlinear springs up to O(h^2) per step). The audit books
// W_c per category (external: gravity, pressure, loads, and drivers, which hold their nodes at
// their velocity against every force on them, -f . kin_v, plus the kinetic energy they set when
// they start them; dissipative: damping; contact) and reports
//   balance error = (E*_n - E*_0 - (W_external - E_dissipated + W_contact)) / (largest energy),
// which measures the error of the discrete dynamics and of the accounting, not the integrator's
// bounded oscillation. Implicit Euler's numerical damping shows as a negative balance error.
// The kinetic energy reported is that of the state after the step; the elastic (and potential)
// energy that of the step's last force evaluation (the state before its last substep: the force
// pass evaluates it beside the forces, at no extra pass).
#pragma once

#include "core/types.hpp"

#include <vector>

namespace harness {

enum class EffectCategory { none, elastic, external, dissipative, contact };
constexpr int kCategories = 5;

struct EnergyLedger {
  double kinetic = 0.0;      // J, of the state after the last step
  double elastic = 0.0;      // J, stored in the springs at the last force evaluation
  double potential = 0.0;    // J, springs and gravity at the last force evaluation
  double initial = 0.0;      // J, kinetic + elastic at the start
  double staggered = 0.0;    // J, E*_n of the last step's start (above)
  double staggered0 = 0.0;   // J, E*_0
  bool started = false;      // E*_0 is known (after the first step)
  double work_external = 0.0;  // J, cumulative: gravity, pressure, loads, drivers
  double dissipated = 0.0;     // J, cumulative, >= 0 for damping
  double work_contact = 0.0;   // J, cumulative; positive: contact injected energy
  double work_contact_peak = 0.0;
  // (E*_n - E*_0) - (W_ext - E_diss + W_contact), over the largest energy involved.
  double balance_error() const;
};

}  // namespace harness
