// Effects: everything a scene can list under "effects" (springs, damping, gravity, pins,
// drivers, pressure, contact) is one Effect, made by the one factory (effects.hpp) from the
// table of effects, and only when the scene lists it. The simulation evaluates the effects it
// built, in table order, through this interface alone:
//   begin_step   once per step, before any force: kinematic constraints (pins, drivers);
//   add_forces   once per (sub)step: adds the effect's forces into World::f;
//   end_step     once per step, after the last position update;
//   detect_ahead, add_forces_shared  the overlap of contact detection with the springs' pass on
//                two threads or more (below);
//   after_integration  after each substep's position update (projection);
//   add_jacobian the linearisation the implicit integrator assembles (LinearSystem);
//   add_stiffness_rows  Gershgorin row sums of |df/dx|, for the explicit stability guard;
//   energy       stored energy of conservative effects (J), for energy balances;
//   category     the energy audit's account its forces work for (energy.hpp).
// An effect that has no stiffness, Jacobian or energy simply keeps the default.
#pragma once

#include "core/energy.hpp"
#include "core/world.hpp"

#include <Eigen/Core>

#include <vector>

namespace harness {

struct StepContext {
  int step = 0;     // 1-based number of the step being taken
  double dt = 0.0;  // s, the step
  double h = 0.0;   // s, the substep (dt / substeps)
  int substeps = 1;
  // The energy audit's side outputs (simulation.hpp), null when it is off: per node the springs'
  // and the dashpots' parts of the force and the springs' energy, written by the force pass.
  Points* f_spring = nullptr;
  Points* f_dashpot = nullptr;
  std::vector<double>* spring_energy = nullptr;
  // The stability guard's rows (stability.hpp), when its check is due this step: the springs' force
  // pass of the first substep adds their Gershgorin rows here (null otherwise).
  std::vector<Vec3>* guard_rows = nullptr;
};

// The linearised backward-Euler system (implicit.hpp) as the effects describe it:
//   per spring k  its stiffness along and across it: K_k = df_i/dx_j = a_k u u^T + t_k (I - u u^T)
//                 (u the unit vector from i to j; a_k the tangent stiffness dT/dl, t_k = max(T/l, 0)
//                 the tension's geometric part, kept non-negative so the block is positive
//                 semi-definite), coupling its two ends with f_i = +K_k (x_j - x_i), f_j = -f_i; and
//                 a dashpot coefficient c_k along the spring (N s/m);
//   per node i    a mass-proportional damping coefficient d_i (kg/s: force -d_i v_i);
//   per contact   (the contact's rules that have a stiffness: the linear penalty) a guest node and
//                 up to three host nodes with coefficients c = (1, -w_1, -w_2, -w_3), the push's
//                 direction n and the stiffness k: the block k (c c^T) (x) (n n^T), positive
//                 semi-definite (the penalty's tangent along n; its part across n, F/d (I - n n^T)
//                 for a rule that turns with the surface, is left out: it is not definite).
//                 Constant-force rules (the paper's, `auto`) have no stiffness: nothing is added,
//                 and at a large step their contact stays explicit.
// The slots start at zero and effects add to them; spring_used says whether any spring slot was
// written (otherwise the integrator skips the springs entirely).
struct ContactBlock {
  int node[4] = {-1, -1, -1, -1};
  double c[4] = {0.0, 0.0, 0.0, 0.0};
  int count = 0;  // nodes used
  Vec3 n = Vec3::Zero();
  double k = 0.0;  // N/m
};

struct LinearSystem {
  std::vector<double> spring_axial;       // a_k, N/m
  std::vector<double> spring_transverse;  // t_k, N/m
  std::vector<double> spring_dashpot;
  std::vector<double> node_damping;
  std::vector<ContactBlock> contacts;
  bool spring_used = false;

  void reset(const World& w) {
    spring_axial.assign(w.springs.size(), 0.0);
    spring_transverse.assign(w.springs.size(), 0.0);
    spring_dashpot.assign(w.springs.size(), 0.0);
    node_damping.assign(static_cast<std::size_t>(w.num_nodes()), 0.0);
    contacts.clear();
    spring_used = false;
  }
};

class Effect {
 public:
  virtual ~Effect() = default;
  virtual const char* name() const = 0;
  // Which account of the energy audit this effect's forces work for (energy.hpp).
  virtual EffectCategory category() const { return EffectCategory::none; }
  virtual void begin_step(World& w, const StepContext& s) { (void)w, (void)s; }
  virtual void add_forces(World& w, const StepContext& s) { (void)w, (void)s; }
  virtual void end_step(World& w, const StepContext& s) { (void)w, (void)s; }
  // Overlap on two threads or more (Simulation::add_forces). ahead_tasks / detect_ahead /
  // ahead_done: work of the next add_forces that needs the positions alone (contact detection),
  // in ahead_tasks() independent tasks done now, each on one thread (several at once), while the
  // first effect's forces are computed on the others; ahead_done() (one thread, after them all)
  // hands them to add_forces.
  // shareable / add_forces_shared: add_forces with its work shared out among the threads of an
  // enclosing parallel region: shareable(), on one thread before the region, gets ready and says
  // whether the effect has such a form worth using now; then every thread of the team calls
  // add_forces_shared, which ends with the team at a barrier. The same forces as add_forces.
  virtual int ahead_tasks() const { return 0; }
  virtual void detect_ahead(const World& w, int task) { (void)w, (void)task; }
  virtual void ahead_done() {}
  virtual bool shareable(const World& w) {
    (void)w;
    return false;
  }
  virtual void add_forces_shared(World& w, const StepContext& s) { (void)w, (void)s; }
  // After each substep's position update (position-based corrections); a correction that moves
  // nodes adds its equivalent force m dx / h^2 into World::f for the energy audit.
  virtual void after_integration(World& w, const StepContext& s) { (void)w, (void)s; }
  virtual bool corrects_positions() const { return false; }  // after_integration does something
  virtual void add_jacobian(const World& w, LinearSystem& sys) const { (void)w, (void)sys; }
  // Adds |df/dx| row sums into rows (one per node); returns false when the effect has no
  // stiffness at all (then it adds nothing).
  virtual bool add_stiffness_rows(const World& w, std::vector<Vec3>& rows) const {
    (void)w, (void)rows;
    return false;
  }
  virtual bool has_stiffness() const { return false; }
  virtual double energy(const World& w) const {
    (void)w;
    return 0.0;
  }
  // Sum over nodes of this effect's last forces (the last add_forces, and after_integration's
  // equivalent forces) dotted with dx (one vector per node), J: the energy audit's work of the
  // effects whose forces it does not keep per node (contact). Only effects of category contact
  // are asked.
  virtual double work(const World& w, const Points& dx) const {
    (void)w, (void)dx;
    return 0.0;
  }
};

}  // namespace harness
