// Builds a World from a Scene (only the listed effects) and advances it step by step.
#pragma once

#include "core/collision/collision.hpp"
#include "core/effects.hpp"
#include "core/implicit.hpp"
#include "core/scene.hpp"
#include "core/world.hpp"

#include <memory>
#include <string>
#include <vector>

namespace harness {

// One contact pair of the scene. `collision` exists only when the scene lists "contact";
// without it the pair is still measured by the references (penetration without contact).
struct PairSlot {
  ContactSpec spec;
  std::string label;  // "host/guest"
  std::unique_ptr<Collision> collision;
  // Of the last step (summed over substeps):
  int contacts = 0;
  double t_detect_us = 0.0, t_eliminate_us = 0.0, force = 0.0;
};

struct StepTimes {
  double step_us = 0.0, physics_us = 0.0, detect_us = 0.0, eliminate_us = 0.0;
};

class Simulation {
 public:
  // Generates the bodies and builds the listed effects. Throws InputError (with the scene's
  // file and key path) for inputs that only show when built: mesh files, empty selections,
  // a dt refused by the stability guard.
  explicit Simulation(const Scene& scene);

  void step();  // advances one step of scene.dt (in `substeps` equal parts)

  World world;
  std::vector<PairSlot> pairs;
  int step_index = 0;  // steps taken
  double time = 0.0;   // s
  StepTimes last;      // timings of the last step
  int substeps = 1;    // explicit substeps per step chosen by the stability guard
  double dt_crit = 0.0;  // s, Gershgorin bound at rest (infinity without springs)
  // Stability guard during the run (explicit integrator): dt_crit is re-evaluated at the
  // current strain every kGuardEvery steps (every step when close to the limit); with guard
  // "substep" the substeps follow it.
  static constexpr int kGuardEvery = 10;
  double dt_crit_min = 0.0;   // smallest dt_crit seen, s
  int max_substeps = 1;       // largest substep count used
  int guard_violations = 0;   // checks with dt > 0.9 dt_crit under guard "refuse"
  ImplicitStats implicit_last;  // of the last implicit solve
  int implicit_max_iterations = 0;
  int implicit_unconverged = 0;

  const Scene& scene() const { return scene_; }
  // Names of the effects built (and simulated), in canonical order.
  std::vector<std::string> effects_simulated() const;
  double kinetic_energy() const;
  double potential_energy() const;  // springs + gravity (conservative effects)

 private:
  void update_kinematics(int step);
  void integrate(double h);

  Scene scene_;
  std::vector<std::unique_ptr<ForceEffect>> forces_;
  bool pins_ = false, drivers_ = false;
  // Nodes fixed by pins (kinematic value 1); driven nodes get value 2 while a driver acts.
  struct DriverNodes {
    std::vector<int> nodes;
    Vec3 velocity;
    int from_step, to_step;
  };
  std::vector<DriverNodes> driver_nodes_;
  std::vector<std::uint8_t> pinned_;
  std::vector<std::uint8_t> driven_now_;  // scratch of update_kinematics
  ImplicitEuler implicit_;
  double dt_crit_last_ = 0.0;  // dt_crit at the last check
  std::vector<Vec3> crit_rows_;  // critical_dt's scratch, kept between checks
  void guard_check();
};

// Critical time step of symplectic Euler from a Gershgorin bound on M^-1 K (spring tangent
// stiffness at the current strain): dt_crit = 2 / sqrt(max_i rowsum_i / m_i). Infinity
// without springs. Kinematic nodes are skipped (they are not integrated). `rows` is scratch
// (resized to the node count; pass the same vector every time to avoid allocating).
double critical_dt(const World& w, std::vector<Vec3>& rows);
double critical_dt(const World& w);

// Global node indices of a body that a selection picks (on the rest positions).
std::vector<int> select_nodes(const World& w, int body, const Selection& sel);

// 64-bit FNV-1a hash of the positions and velocities, as 16 hex digits.
std::string state_hash(const World& w);

}  // namespace harness
