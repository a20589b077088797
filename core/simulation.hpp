// Builds a World from a Scene, with only the effects the scene lists, and advances it step by
// step. Built in named steps: the world (world_build.hpp: bodies laid out in one set of arrays),
// the kinematic selections (pins, drivers, loads: resolved and checked whether listed or not),
// the contact pairs, the effects (effects/effects.hpp: one factory, one interface), the
// stability guard, and the energy audit (energy_audit.hpp).
#pragma once

#include <cstdint>

#include "core/collision/collision.hpp"
#include "core/effects/effects.hpp"
#include "core/energy_audit.hpp"
#include "core/engine.hpp"
#include "core/implicit.hpp"
#include "core/scene/scene.hpp"
#include "core/stability.hpp"
#include "core/state_hash.hpp"
#include "core/world.hpp"
#include "core/world_build.hpp"

#include <memory>
#include <string>
#include <vector>

namespace harness {

struct SimulationOptions {
  ExactDetectorMaker exact_detectors = nullptr;  // reference::make_exact_detector where linked
  // The energy audit and the force residual (energy.hpp): booked in the position update's pass
  // (the springs' energy in the force pass); they only read the state, whose bits never depend on
  // this.
  bool audit = true;
  // A peer engine (engine.hpp) steps the world instead of the effects and the integrator; the
  // contact effect is then not built (the engine handles the pairs) and the energy audit keeps
  // only the kinetic and elastic energies (no work booked) and the force residual.
  EngineMaker engine = nullptr;
  // With two threads or more, contact detection overlapping the springs' pass (add_forces):
  // automatic (when the last detection took at least kOverlapShare of the pass alone), always, or
  // never. Only the time depends on it, never the bits (tests run it always).
  enum class Overlap { automatic, always, never };
  Overlap overlap = Overlap::automatic;
  // The node order of the world (node_order.hpp, world_build.hpp): a layout only; outputs keep the
  // scene's numbering.
  WorldBuild layout;
  // An ensemble member's initial jitter (harness run --ensemble): every free node's initial
  // position moved by up to jitter times its body's rest spring length per coordinate, pseudo-random
  // from jitter_seed and the node's scene index (the same displacement in every node order). 0: none.
  double jitter = 0.0;
  std::uint64_t jitter_seed = 0;
  // Contact responses of the program's own, by pair index (ContactResponse, collision.hpp; an empty
  // one or a pair past the end: the scene's force rule). The scene must list "contact", the pair
  // must eliminate with forces (line, plane) and the integrator be explicit: they report no
  // stiffness (InputError otherwise, naming the key).
  std::vector<OwnResponse> responses;
  // Forces added by hand (Simulation::add_next_force) are accepted and booked by the audit as
  // external work.
  bool user_forces = false;
};

// Wall time of the last step, microseconds (steady_clock). physics: everything but the contact
// pairs' detection and elimination (the step's time minus theirs: where detection overlaps the
// springs' pass on two threads, the overlap is counted once, in detect).
struct StepTimes {
  double step_us = 0.0, physics_us = 0.0, detect_us = 0.0, eliminate_us = 0.0;
};

struct SimulationStats {
  StabilityStats stability;
  ImplicitStats implicit_last;   // of the last implicit solve
  int implicit_max_iterations = 0;
  long long implicit_iterations = 0;  // summed over the solves
  long long implicit_solves = 0;
  int implicit_unconverged = 0;  // solves that missed the CG tolerance
};

// SimulationOptions::jitter applied to w (free nodes only).
void jitter_positions(World& w, double share, std::uint64_t seed);

class Simulation {
 public:
  // Throws InputError (with the scene's file and key path) for inputs that only show when
  // built: mesh files, empty selections, a dt refused by the stability guard.
  explicit Simulation(const Scene& scene, const SimulationOptions& options = {});

  void step();  // advances one step of scene.dt (in `substeps` equal parts)
  // Puts back a state (after a failed step): positions, velocities and the step count.
  void restore(const Points& x, const Points& v, int step);

  World& world() { return world_; }
  const World& world() const { return world_; }
  const std::vector<Pair>& pairs() const { return pairs_; }
  const Scene& scene() const { return scene_; }
  int step_index() const { return step_index_; }  // steps taken
  double time() const { return step_index_ * scene_.dt; }  // s
  const StepTimes& last() const { return last_; }
  const SimulationStats& stats() const { return stats_; }
  double implicit_tolerance() const { return implicit_.tolerance; }  // the CG's relative residual
  const Effects& effects() const { return effects_; }
  const Kinematics& kinematics() const { return kinematics_; }
  const StepEngine* engine() const { return engine_.get(); }  // null: the harness's own
  // Names of the effects simulated, in canonical order.
  std::vector<std::string> effects_simulated() const;
  double kinetic_energy() const;    // of the current state (kinetic_energy(World), world.hpp)
  double potential_energy() const;  // stored energy of the built effects (springs, gravity)
  double elastic_energy() const;    // stored in the springs
  // The energy audit so far (audit on); zeros otherwise. energy() evaluates the springs' energy
  // of the last step where the step left it pending (energy_audit.hpp: only when read; a pass
  // over the springs); energy_booked() does not: its works, kinetic energy and residual are the
  // last step's, its elastic and potential energies and E*_n those of the last step evaluated
  // (energy_current() says whether that is the last step).
  const EnergyLedger& energy() const;
  // The steps energy() will be read on, when they are known: every k-th (k > 0; the recorder's
  // schedule). The audit then takes the springs' energy from those steps' force pass instead of
  // evaluating it afterwards; a read on another step still evaluates it then.
  void energy_read_every(int k) {
    if (audit_) audit_->read_every(k);
  }
  const EnergyLedger& energy_booked() const;
  bool energy_current() const { return !audit_ || !audit_->elastic_pending(); }
  // Restarts the audit from the current state (after a caller changed it by hand).
  void reset_energy();
  // A caller changed velocities by hand and the kinetic energy by dE (J): booked as external work,
  // the audit goes on (O(1); a change of positions needs reset_energy()).
  void book_kinetic_change(double dE);
  // A force (N) on world node i in every substep of the next step only (SimulationOptions::
  // user_forces; std::logic_error without it); booked as external work.
  void add_next_force(int i, const Vec3& f);
  // |net force on the free nodes| / |applied forces on them| (gravity, pressure, loads), or,
  // where nothing is applied, over the largest |spring forces| of the run so far, at the start
  // of the last substep; 0 without either, NaN with the audit off.
  double residual() const;
  double critical_dt() const;       // of the built effects at the current state, s
  bool audited() const { return audit_ != nullptr; }

 private:
  void build_pairs();
  void attach_responses(const SimulationOptions& options);
  void build_effects(const SimulationOptions& options);
  void integrate(const StepContext& s);
  void add_forces(StepContext& s);
  void after_integration(const StepContext& s);
  void engine_step();
  double elastic_energy(const World& w) const;  // of the built effects at w's positions

  Scene scene_;
  World world_;
  Kinematics kinematics_;
  std::vector<Pair> pairs_;
  Effects effects_;
  Effect* ahead_ = nullptr;  // the contact effect, when it can detect ahead (add_forces)
  double alone_us_ = 0.0;    // the first effect's forces when they last ran alone, us (add_forces)
  SimulationOptions::Overlap overlap_ = SimulationOptions::Overlap::automatic;
  static constexpr double kOverlapShare = 0.4;
  std::unique_ptr<StabilityGuard> guard_;
  std::unique_ptr<StepEngine> engine_;
  Points engine_v_prev_;  // velocities before the engine's step (its residual)
  ImplicitEuler implicit_;
  LinearSystem system_;
  int step_index_ = 0;
  bool external_ = false;   // some external effect (gravity, pressure, loads) is built
  bool corrects_ = false;   // some effect corrects positions after integration (projection)
  Points f_ext_;            // this substep's external forces: those effects add here (then into f)
  bool user_forces_ = false;                       // SimulationOptions::user_forces
  std::vector<std::pair<int, Vec3>> next_forces_;  // add_next_force: for the next step
  std::unique_ptr<EnergyAudit> audit_;  // null: the audit is off
  StepTimes last_;
  SimulationStats stats_;
};

}  // namespace harness
