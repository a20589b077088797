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
//
// What it costs: the work of every account, the kinetic energy and the force residual are booked
// every step (the works are sums over every interval, the residual decides when a run settles);
// the springs' energy, which costs a transcendental function per spring, is evaluated only when
// it is read. On the fused path (symplectic Euler without position corrections) a step leaves it
// pending, and complete() evaluates it at the step's last force point x_n = x_{n+1} - dx (dx the
// displacement the step applied, kept for the works' closing); the first step after a reset and
// every step of the general path evaluate it in the force pass as before. Simulation::energy()
// completes it; Simulation::energy_booked() does not (the recorder reads the energy on the steps
// a run measures and the last: core/run/recorder.cpp).
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

  // Points the step's force pass at the audit's per-node outputs; lazy_elastic: the springs'
  // energy may be left pending (the fused path: the step's displacement is exactly what it added).
  // It is not on the steps read_every (when > 0) divides: those that will read it (a run's
  // recorder's), which get it from the force pass, at the cost of the law's energy beside its force.
  void attach(StepContext& ctx, bool lazy_elastic);
  void read_every(int k) { read_every_ = k; }
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

  // The state's kinetic energy changed by dE (J) from outside the step (velocities set by hand):
  // booked as external work.
  void book_external(double dE) {
    ledger_.kinetic += dE;
    ledger_.work_external += dE;
  }
  // Restarts the ledger from a state of the given energies (J).
  void reset(double kinetic, double elastic, double potential);

  const EnergyLedger& ledger() const { return ledger_; }
  // The elastic and potential energies and E*_n of the last step are not evaluated yet.
  bool elastic_pending() const { return elastic_pending_; }
  // Evaluates them at the last step's force point: w.x is swapped with x_n for elastic(w) and
  // back (the state's bits are unchanged).
  template <class Elastic>
  void complete(World& w, Elastic&& elastic) {
    if (!elastic_pending_) return;
    for (std::size_t i = 0; i < w.x.size(); ++i) x_scratch_[i] = w.x[i] - disp_prev_[i];
    if (setup_.gravity) gravity_potential_ = gravity_potential(w, x_scratch_);
    w.x.swap(x_scratch_);
    const double U = elastic(static_cast<const World&>(w));
    w.x.swap(x_scratch_);
    book_elastic(U);
  }
  // The force residual (simulation.hpp, Simulation::residual).
  double residual() const { return residual_; }

 private:
  void close_substep(const double* sums);
  void book_elastic(double U);
  double gravity_potential(const World& w, const Points& x) const;

  AuditSetup setup_;
  // Per node: the force pass's springs' and dashpots' parts, the springs' energy, the previous
  // substep's displacement, the velocities before the update (general path only), the body's
  // mass damping where damping is built.
  Points f_spring_, f_dashpot_, disp_prev_, v_before_, x_scratch_;
  std::vector<double> node_energy_;
  std::vector<double> mass_damping_;
  std::vector<double> m3_, inv_m3_, mdm3_;  // per coordinate: mass, 1 / mass, mass damping x mass
  std::vector<double> chunk_sums_;  // the booking pass's partial sums, per chunk of nodes
  bool first_substep_ = false;
  bool energy_in_pass_ = true;      // this step's force pass writes the springs' energy
  int read_every_ = 0;              // the steps the energy will be read on (read_every)
  bool elastic_pending_ = false;    // the last step's elastic energy is not evaluated yet
  double ke_staggered_ = 0.0;       // J, the kinetic part of E*_n of the last step
  double gravity_potential_ = 0.0;  // J, at the last step's force point
  // Work of the interval ahead of the last force point, booked when the next one closes it
  // (energy.hpp): external, dissipative, drivers, contact.
  double pending_[4] = {0.0, 0.0, 0.0, 0.0};
  EnergyLedger ledger_;
  double residual_ = 0.0;
  double spring_force_peak_ = 0.0;  // largest |spring forces|^2 on the free nodes so far
};

}  // namespace harness
