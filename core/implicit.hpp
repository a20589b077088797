// Linearised backward Euler (Baraff and Witkin 1998) for stiff scenes:
//   (M - h D - h^2 K) dv = h (f0 + h K v0),   v1 = v0 + dv,   x1 = x0 + h v1
// f0 is every force of the step at (x0, v0) (w.f, contact included, treated explicitly);
// K = df/dx and D = df/dv as the simulated effects describe them (effect.hpp, LinearSystem):
// per spring a stiffness block and a dashpot along it, per node mass-proportional damping.
// Kinematic nodes (pins, drivers) are not unknowns: pinned nodes stay put, driven ones move
// with their kin_v; their coupling enters the right-hand side through K v0. The system is
// symmetric positive definite (the effects keep their blocks so), solved by conjugate gradient.
#pragma once

#include "core/effects/effect.hpp"
#include "core/world.hpp"

#include <Eigen/Sparse>

#include <vector>

namespace harness {

struct ImplicitStats {
  int iterations = 0;     // conjugate-gradient iterations of the last solve
  double error = 0.0;     // relative residual reached
  bool converged = true;
};

class ImplicitEuler {
 public:
  ImplicitStats step(World& w, double h, const LinearSystem& sys);
  double tolerance = 1e-9;   // relative residual of CG
  int max_iterations = 1000;

 private:
  void assemble_springs(const World& w, double h, const LinearSystem& sys);

  std::vector<int> dof_;  // node -> first unknown (3 per free node), -1 for kinematic nodes
  std::vector<Eigen::Triplet<double>> triplets_;
  Eigen::SparseMatrix<double> A_;
  Eigen::VectorXd b_, dv_;
  Eigen::ConjugateGradient<Eigen::SparseMatrix<double>, Eigen::Lower | Eigen::Upper> cg_;
};

}  // namespace harness
