// The energy audit of a run and its force residual (energy.hpp states what is booked and why):
// the ledger, the per-node side outputs the force pass writes for it (the springs' and the
// dashpots' forces, the springs' energy per node), and the booking, which runs in the same pass
// over the nodes as the position update (symplectic Euler without position corrections:
// integrate_and_book) or right after the integrator and the corrections (book). Everything here
// only reads the state the step computes; the state's bits never depend on whether the audit is
// on (SimulationOptions::audit).
//
// The kinetic energy is booked once per step, in that pass: the kinetic energy after the step,
// and in a step's first substep, when drivers start or stop nodes, the kinetic energy the step
// began with (the drivers' velocities set), whose change since the last step is the work they
// put in.
#pragma once

#include "core/effects/effect.hpp"
#include "core/energy.hpp"
#include "core/world.hpp"

#include <vector>

namespace harness {

// What the audit books: which accounts exist in the built simulation.
struct AuditSetup {
  bool springs = false;     // the springs effect is built: their forces and energy per node
  bool damping = false;     // the damping effect: the dashpots' forces per node, mass damping
  bool gravity = false;     // the gravity effect: its potential
  Vec3 gravity_acceleration = Vec3::Zero();
  bool drivers = false;     // drivers are built: the kinetic energy they set is work put in
  const Points* f_ext = nullptr;    // the external effects' forces of the substep (null: none built)
  const Effect* contact = nullptr;  // the contact effect, for its work (null: not built)
};

class EnergyAudit {
 public:
  EnergyAudit(const World& w, const AuditSetup& setup);

  // Points the step's force pass at the audit's per-node outputs.
  void attach(StepContext& ctx);
  // The springs' forces per node (null without springs): a peer engine's residual scale.
  Points* spring_forces() { return f_spring_.empty() ? nullptr : &f_spring_; }
  // Before a step's first substep.
  void begin_step() { first_substep_ = true; }
  // Symplectic Euler (integrator.hpp: the same operations, bit for bit) with the booking in the
  // same pass over the nodes.
  void integrate_and_book(World& w, const StepContext& s);
  // The general path: velocities kept before the integrator (keep_velocities), booked after it
  // and the position corrections (book).
  void keep_velocities(const World& w);
  void book(const World& w, const StepContext& s);
  // After a step's last substep.
  void end_step() { ledger_.work_contact_peak = std::max(ledger_.work_contact_peak, ledger_.work_contact); }

  // A peer engine's step (engine.hpp): the energies it ended with, and the force residual with the
  // net force on a free node taken as the one that changed its momentum in the step,
  // m (v - v_prev) / dt; the force pass has just written the external and springs' forces at the
  // new state (the residual's scales).
  void engine_step(const World& w, const Points& v_prev, double dt, double kinetic, double elastic, double potential);

  // Restarts the ledger from a state of the given energies (J).
  void reset(double kinetic, double elastic, double potential);

  const EnergyLedger& ledger() const { return ledger_; }
  // The force residual (simulation.hpp, Simulation::residual).
  double residual() const { return residual_; }

 private:
  void close_substep(const double* sums);

  AuditSetup setup_;
  // Per node: the force pass's springs' and dashpots' parts, the springs' energy, the previous
  // substep's displacement, the velocities before the update (general path only), the body's
  // mass damping where damping is built.
  Points f_spring_, f_dashpot_, disp_prev_, v_before_;
  std::vector<double> node_energy_;
  std::vector<double> mass_damping_;
  std::vector<double> chunk_sums_;  // the booking pass's partial sums, per chunk of nodes
  bool first_substep_ = false;
  // Work of the interval ahead of the last force point, booked when the next one closes it
  // (energy.hpp): external, dissipative, drivers, contact.
  double pending_[4] = {0.0, 0.0, 0.0, 0.0};
  EnergyLedger ledger_;
  double residual_ = 0.0;
  double spring_force_peak_ = 0.0;  // largest |spring forces|^2 on the free nodes so far
};

}  // namespace harness
