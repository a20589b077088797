// Bullet's soft bodies as a peer engine (core/engine.hpp), `harness run SCENE --engine bullet`.
// Bullet (Debian's libbullet-dev, its double-precision build) is linked only here.
//
// The same model, built in a btSoftRigidDynamicsWorld and stepped with Bullet's own solver
// (stepSimulation(dt, 0): one step of dt; Bullet's position solver, eSolverPresets::Positions):
//   nodes     every node of every body (surface and interior), at the same positions and with
//             the same lumped masses and initial velocities; faces = the body's surface triangles;
//   links     one Bullet link per spring, rest length = the spring's rest length;
//   stiffness Bullet's link stiffness kLST is a fraction of a link's violation corrected per
//             position iteration, shared by inverse mass. A spring of stiffness k between masses
//             m_a, m_b moves its ends by dt^2 k e / m per step (symplectic Euler, e the
//             extension); the link does the same to first order in e when
//                 kLST = k dt^2 (1/m_a + 1/m_b) / iterations
//             (one Bullet material per link). A link whose kLST would exceed 1 is refused
//             (time.dt: Bullet's solver would overshoot);
//   pins, drivers   kinematic nodes: inverse mass 0 in Bullet during the steps they are held or
//             driven, velocity 0 or the driver's (the links' constants keep the free masses);
//   gravity   the world's gravity when the scene lists "gravity", else none;
//   damping   the material's mass_damping c (1/s) as Bullet's velocity damping kDP = c dt;
//   contact   vertex-face soft-soft collision (fCollision::VF_SS) between the bodies of each
//             contact pair only (collision filter masks), no friction (kDF = 0), contact hardness
//             kSHR = 1, and a collision margin per body (recorded in summary.json "engine"):
//             a node within margin_a + margin_b (+ twice its step displacement) of a face of the
//             other body is put back to that distance, along the line from the face to the node.
//             The pair's detector, eliminator and force are not used.
// Refused with exit 2 naming the key: spring laws other than linear (material.law), dashpot
// damping along the springs (material.damping > 0 with "damping"), pressure and loads, a kDP
// or a kLST of 1 or more, more than 30 bodies. time.integrator and time.guard are replaced by
// Bullet's solver (the guard's refusal of a dt still applies: it is checked before).
#pragma once

#include "core/engine.hpp"

#include <memory>
#include <string>

namespace harness {

struct BulletOptions {
  double margin = 0.0;  // m, per body; 0: automatic, kMarginFraction x the body's mean surface edge
  int iterations = 1;   // Bullet's position iterations per step (btSoftBody::Config::piterations)
  static constexpr double kMarginFraction = 0.05;
};

EngineMaker make_bullet_engine(const BulletOptions& options);

// Bullet's collision step alone, for the bench (experiments/bench.hpp, row bullet_collide): the
// two bodies of a world as soft bodies (nodes and faces, automatic margins, VF_SS between them;
// the face trees built by incremental insertion, not by Bullet's initializeFaceTree, which is
// quadratic in the face count); collide() refits their trees (btSoftBody::predictMotion, nodes at
// rest) and runs the world's collision pass, and returns the vertex-face contacts it generated.
class BulletCollisionBench {
 public:
  BulletCollisionBench(const World& w, int host, int guest);
  ~BulletCollisionBench();
  BulletCollisionBench(const BulletCollisionBench&) = delete;
  BulletCollisionBench& operator=(const BulletCollisionBench&) = delete;
  int collide();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

std::string bullet_version();  // "3.24 (double)"

}  // namespace harness
