// Linearised backward Euler (Baraff and Witkin 1998) for stiff scenes:
//   (M - h D - h^2 K) dv = h (f0 + h K v0),   v1 = v0 + dv,   x1 = x0 + h v1
// f0 is every force of the step at (x0, v0) (w.f, contact included);
// K = df/dx and D = df/dv as the simulated effects describe them (effect.hpp, LinearSystem):
// per spring a stiffness block and a dashpot along it, per node mass-proportional damping, per
// contact of a rule with a stiffness (the linear penalty) k n n^T between the guest node and its
// host nodes: that contact is in the system, so a large step with it stays stable. Constant-force
// rules have no stiffness and stay explicit.
// Kinematic nodes (pins, drivers) are not unknowns: pinned nodes stay put, driven ones move
// with their kin_v; their coupling enters the right-hand side through K v0. The system is
// symmetric positive definite (the effects keep their blocks so), solved by conjugate gradient.
//
// Matrix-free: no matrix is assembled. Per step each spring's block
// B = h^2 K_k + h c_k u u^T = alpha u u^T + beta I (alpha = h^2 (a_k - t_k) + h c_k, beta = h^2 t_k)
// is kept as (u, alpha, beta); each CG iteration applies A p = M' p + sum_k B_k (p_i - p_j)
// (scattered to both ends) in one pass over the springs, the cost of one force pass. Preconditioner: each free node's
// 3x3 diagonal block of A, inverted (block Jacobi). Warm start: the last step's dv. Iterations
// per step are in ImplicitStats (and summary.json stability.implicit).
#pragma once

#include "core/effects/effect.hpp"
#include "core/world.hpp"

#include <Eigen/Core>

#include <vector>

namespace harness {

struct ImplicitStats {
  int iterations = 0;     // conjugate-gradient iterations of the last solve
  double error = 0.0;     // relative residual reached, |b - A dv| / |b|
  bool converged = true;
};

class ImplicitEuler {
 public:
  ImplicitStats step(World& w, double h, const LinearSystem& sys);
  double tolerance = 1e-9;   // relative residual of CG
  int max_iterations = 1000;

 private:
  void prepare(const World& w, double h, const LinearSystem& sys);
  void apply(const World& w, const Points& p, Points& y) const;  // y = A p over the free nodes

  struct Block {
    Vec3 u;
    double alpha, beta;  // B_k = alpha u u^T + beta I (zero for a spring between kinematic nodes)
  };
  std::vector<Block> block_;
  std::vector<double> diag_;            // per node, m (1 + h d)
  std::vector<Eigen::Matrix3d> pinv_;   // per node, the inverse of its diagonal block (free nodes)
  std::vector<int> kinematic_;          // the nodes that are not unknowns
  struct Contact {
    ContactBlock block;
    double hk;  // h^2 k
  };
  std::vector<Contact> contacts_;       // the contacts' blocks (LinearSystem::contacts)
  using Vec6 = Eigen::Matrix<double, 6, 1>;
  std::vector<Vec6, Eigen::aligned_allocator<Vec6>> sym_;  // per node, the springs' diagonal block
  Points b_, x_, r_, z_, p_, q_;
  Points warm_;                         // the last step's dv (the warm start)
};

}  // namespace harness
