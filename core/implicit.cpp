#include "core/implicit.hpp"

#include "core/integrator.hpp"

namespace harness {

// Each spring couples i and j with a 3x3 block B = h^2 K_k + h c_k u u^T:
// A_ii += B, A_jj += B, A_ij = A_ji -= B; the right-hand side gets h^2 (K v0): on i,
// K_k (v_j - v_i), on j the opposite.
void ImplicitEuler::assemble_springs(const World& w, double h, const LinearSystem& sys) {
  for (std::size_t k = 0; k < w.springs.size(); ++k) {
    const int i = w.springs.ends[k][0], j = w.springs.ends[k][1];
    const int di = dof_[i], dj = dof_[j];
    if (di < 0 && dj < 0) continue;
    const Vec3 d = w.x[j] - w.x[i];
    const double l = d.norm();
    if (l <= 0.0) continue;
    const Vec3 u = d / l;
    const Eigen::Matrix3d uu = u * u.transpose();
    const Eigen::Matrix3d& Ks = sys.spring_stiffness[k];
    const double c = sys.spring_dashpot[k];
    const Eigen::Matrix3d B = h * h * Ks + h * c * uu;
    const Vec3 kv = h * h * (Ks * (w.v[j] - w.v[i]));
    for (int a = 0; a < 3; ++a)
      for (int bb = 0; bb < 3; ++bb) {
        const double val = B(a, bb);
        if (val == 0.0) continue;
        if (di >= 0) triplets_.emplace_back(di + a, di + bb, val);
        if (dj >= 0) triplets_.emplace_back(dj + a, dj + bb, val);
        if (di >= 0 && dj >= 0) {
          triplets_.emplace_back(di + a, dj + bb, -val);
          triplets_.emplace_back(dj + a, di + bb, -val);
        }
      }
    if (di >= 0) b_.segment<3>(di) += kv;
    if (dj >= 0) b_.segment<3>(dj) -= kv;
  }
}

ImplicitStats ImplicitEuler::step(World& w, double h, const LinearSystem& sys) {
  const int n = w.num_nodes();
  dof_.assign(n, -1);
  int ndof = 0;
  for (int i = 0; i < n; ++i)
    if (w.is_free(i)) dof_[i] = 3 * ndof++;
  // Driven nodes move with their prescribed velocity during the step.
  for (int i = 0; i < n; ++i)
    if (w.kinematic[i] == Kinematic::driven) w.v[i] = w.kin_v[i];

  b_.setZero(3 * ndof);
  triplets_.clear();
  for (int i = 0; i < n; ++i) {
    const int d = dof_[i];
    if (d < 0) continue;
    for (int a = 0; a < 3; ++a) {
      triplets_.emplace_back(d + a, d + a, w.m[i]);
      b_[d + a] = h * w.f[i][a];
    }
  }
  for (int i = 0; i < n; ++i)  // mass-proportional damping: -D = alpha m I
    if (dof_[i] >= 0 && sys.node_damping[i] != 0.0)
      for (int a = 0; a < 3; ++a) triplets_.emplace_back(dof_[i] + a, dof_[i] + a, h * sys.node_damping[i] * w.m[i]);
  if (sys.spring_used) assemble_springs(w, h, sys);
  A_.resize(3 * ndof, 3 * ndof);
  A_.setFromTriplets(triplets_.begin(), triplets_.end());
  cg_.setTolerance(tolerance);
  cg_.setMaxIterations(max_iterations);
  cg_.compute(A_);
  dv_ = cg_.solve(b_);
  ImplicitStats st;
  st.iterations = static_cast<int>(cg_.iterations());
  st.error = cg_.error();
  st.converged = cg_.info() == Eigen::Success;
  update_nodes(w, h, [this, &w](int i) { w.v[i] += dv_.segment<3>(dof_[i]); });
  return st;
}

}  // namespace harness
