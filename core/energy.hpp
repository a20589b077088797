// The energy audit of a run. Every effect that adds forces belongs to one category
// (Effect::category()); the simulation keeps, per substep, the force each category added (by
// snapshots of World::f between categories, so auditing never changes the state's bits) and
// after the position update books each category's work
//   W_c = h sum_i f_c,i . (v_i before + v_i after) / 2    over the nodes that move,
// which for symplectic Euler makes the kinetic energy change of the free nodes exactly the sum
// of the categories' work. A driver holds its nodes at their velocity against every force on
// them, so its work is -h sum f_i . kin_v over its nodes, plus the kinetic energy it sets when
// it starts them. The balance
//   E_kin + E_elastic - (E_kin + E_elastic)_0 = W_external - E_dissipated + W_contact
// then closes up to the springs' discretisation (their work against the change of their
// energy: bounded for symplectic Euler) and, for implicit Euler, its numerical damping.
#pragma once

#include "core/types.hpp"

#include <vector>

namespace harness {

enum class EffectCategory { none, elastic, external, dissipative, contact };
constexpr int kCategories = 5;

struct EnergyLedger {
  double kinetic = 0.0;      // J, now
  double elastic = 0.0;      // J, stored in the springs now
  double initial = 0.0;      // J, kinetic + elastic at the start
  double work_external = 0.0;  // J, cumulative: gravity, pressure, loads, drivers
  double dissipated = 0.0;     // J, cumulative, >= 0 for damping
  double work_contact = 0.0;   // J, cumulative; positive: contact injected energy
  double work_contact_peak = 0.0;
  // (E - E0) - (W_ext - E_diss + W_contact), over the largest energy involved.
  double balance_error() const;
};

}  // namespace harness
