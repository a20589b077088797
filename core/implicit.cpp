#include "core/implicit.hpp"

#include "core/integrator.hpp"

#include <Eigen/Dense>

#include <cmath>

namespace harness {


// Each spring couples i and j with a 3x3 block B = h^2 K_k + h c_k u u^T:
// A_ii += B, A_jj += B, A_ij = A_ji = -B; the right-hand side gets h^2 (K v0): on i,
// K_k (v_j - v_i), on j the opposite. The right-hand side's mass part: h f0.
void ImplicitEuler::prepare(const World& w, double h, const LinearSystem& sys) {
  const int n = w.num_nodes();
  b_.assign(n, Vec3::Zero());
  diag_.assign(n, 0.0);
  for (int i = 0; i < n; ++i) {
    if (!w.is_free(i)) continue;
    diag_[i] = w.m[i] * (1.0 + h * sys.node_damping[i]);
    b_[i] = h * w.f[i];
  }
  // Per node the springs' part of its diagonal block, symmetric: (xx, yy, zz, xy, xz, yz).
  sym_.assign(n, Vec6::Zero());
  const std::size_t ns = w.springs.size();
  block_.resize(sys.spring_used ? ns : 0);
  if (sys.spring_used) {
    for (std::size_t k = 0; k < ns; ++k) {
      const int i = w.springs.ends[k][0], j = w.springs.ends[k][1];
      const bool fi = w.is_free(i), fj = w.is_free(j);
      Block& bk = block_[k];
      bk = Block{Vec3::Zero(), 0.0, 0.0};
      if (!fi && !fj) continue;
      const Vec3 d = w.x[j] - w.x[i];
      const double l = d.norm();
      if (l <= 0.0) continue;
      const Vec3 u = d / l;
      const double a = sys.spring_axial[k], t = sys.spring_transverse[k];
      bk.u = u;
      bk.alpha = h * h * (a - t) + h * sys.spring_dashpot[k];
      bk.beta = h * h * t;
      // h^2 K_k (v_j - v_i) with K_k = (a - t) u u^T + t I
      const Vec3 dv = w.v[j] - w.v[i];
      const Vec3 kv = (h * h) * ((a - t) * u.dot(dv) * u + t * dv);
      Vec6 B;
      B << bk.alpha * u.x() * u.x() + bk.beta, bk.alpha * u.y() * u.y() + bk.beta, bk.alpha * u.z() * u.z() + bk.beta,
          bk.alpha * u.x() * u.y(), bk.alpha * u.x() * u.z(), bk.alpha * u.y() * u.z();
      if (fi) b_[i] += kv, sym_[i] += B;
      if (fj) b_[j] -= kv, sym_[j] += B;
    }
  }
  // The contacts' blocks h^2 k (c c^T) (x) (n n^T): the right-hand side's h^2 (df/dx) v0 = -h^2 k
  // c_a (n . sum_b c_b v_b) n on node a, and each node's diagonal part h^2 k c_a^2 n n^T.
  contacts_.clear();
  for (const ContactBlock& cb : sys.contacts) {
    Contact c = {cb, h * h * cb.k};
    double sv = 0.0;
    for (int a = 0; a < cb.count; ++a) sv += cb.c[a] * cb.n.dot(w.v[cb.node[a]]);
    for (int a = 0; a < cb.count; ++a) {
      const int i = cb.node[a];
      if (!w.is_free(i)) continue;
      b_[i] -= (c.hk * cb.c[a] * sv) * cb.n;
      const double s2 = c.hk * cb.c[a] * cb.c[a];
      const Vec3& n = cb.n;
      Vec6 B;
      B << s2 * n.x() * n.x(), s2 * n.y() * n.y(), s2 * n.z() * n.z(), s2 * n.x() * n.y(), s2 * n.x() * n.z(),
          s2 * n.y() * n.z();
      sym_[i] += B;
    }
    contacts_.push_back(c);
  }
  kinematic_.clear();
  for (int i = 0; i < n; ++i)
    if (!w.is_free(i)) kinematic_.push_back(i);
  pinv_.assign(n, Eigen::Matrix3d::Zero());
  for (int i = 0; i < n; ++i) {
    if (!w.is_free(i)) continue;
    const Vec6& a = sym_[i];
    Eigen::Matrix3d D;
    D << a[0] + diag_[i], a[3], a[4], a[3], a[1] + diag_[i], a[5], a[4], a[5], a[2] + diag_[i];
    pinv_[i] = D.inverse();
  }
}

void ImplicitEuler::apply(const World& w, const Points& p, Points& y) const {
  const int n = w.num_nodes();
  for (int i = 0; i < n; ++i) y[i] = diag_[i] * p[i];  // kinematic nodes: diag 0, p 0
  for (std::size_t k = 0; k < block_.size(); ++k) {
    const int i = w.springs.ends[k][0], j = w.springs.ends[k][1];
    const Block& b = block_[k];
    const Vec3 e = p[i] - p[j];  // p of a kinematic node is 0
    const Vec3 d = (b.alpha * b.u.dot(e)) * b.u + b.beta * e;
    y[i] += d;
    y[j] -= d;
  }
  for (const Contact& c : contacts_) {
    const ContactBlock& cb = c.block;
    double s = 0.0;
    for (int a = 0; a < cb.count; ++a) s += cb.c[a] * cb.n.dot(p[cb.node[a]]);
    for (int a = 0; a < cb.count; ++a) y[cb.node[a]] += (c.hk * cb.c[a] * s) * cb.n;
  }
  for (int i : kinematic_) y[i].setZero();
}

ImplicitStats ImplicitEuler::step(World& w, double h, const LinearSystem& sys) {
  const int n = w.num_nodes();
  // Driven nodes move with their prescribed velocity during the step.
  for (int i = 0; i < n; ++i)
    if (w.kinematic[i] == Kinematic::driven) w.v[i] = w.kin_v[i];
  prepare(w, h, sys);
  if (static_cast<int>(warm_.size()) != n) warm_.assign(n, Vec3::Zero());
  x_.assign(n, Vec3::Zero());
  r_.assign(n, Vec3::Zero());
  z_.assign(n, Vec3::Zero());
  p_.assign(n, Vec3::Zero());
  q_.assign(n, Vec3::Zero());
  for (int i = 0; i < n; ++i)
    if (w.is_free(i)) x_[i] = warm_[i];
  // Preconditioned conjugate gradient from the warm start. Kinematic entries of b, r, z, p and q
  // stay zero (b and pinv are zero there, apply() zeroes them), so the dot products need no test.
  apply(w, x_, q_);
  double bb = 0.0, rr = 0.0;
  for (int i = 0; i < n; ++i) {
    r_[i] = b_[i] - q_[i];
    bb += b_[i].squaredNorm();
    rr += r_[i].squaredNorm();
  }
  const double bnorm = std::sqrt(bb);
  ImplicitStats st;
  const double target = tolerance * bnorm;
  double rnorm = std::sqrt(rr);
  if (bnorm == 0.0) {
    for (int i = 0; i < n; ++i) x_[i].setZero();
    rnorm = 0.0;
  }
  int it = 0;
  if (rnorm > target) {
    double rz = 0.0;
    for (int i = 0; i < n; ++i) {
      z_[i] = pinv_[i] * r_[i];
      p_[i] = z_[i];
      rz += r_[i].dot(z_[i]);
    }
    for (; it < max_iterations; ++it) {
      apply(w, p_, q_);
      double pq = 0.0;
      for (int i = 0; i < n; ++i) pq += p_[i].dot(q_[i]);
      if (!(pq > 0.0)) break;  // not positive definite along p (or p vanished)
      const double alpha = rz / pq;
      rr = 0.0;
      for (int i = 0; i < n; ++i) {
        x_[i] += alpha * p_[i];
        r_[i] -= alpha * q_[i];
        rr += r_[i].squaredNorm();
      }
      rnorm = std::sqrt(rr);
      if (rnorm <= target) {
        ++it;
        break;
      }
      double rz_new = 0.0;
      for (int i = 0; i < n; ++i) {
        z_[i] = pinv_[i] * r_[i];
        rz_new += r_[i].dot(z_[i]);
      }
      const double beta = rz_new / rz;
      rz = rz_new;
      for (int i = 0; i < n; ++i) p_[i] = z_[i] + beta * p_[i];
    }
  }
  st.iterations = it;
  st.error = bnorm > 0.0 ? rnorm / bnorm : 0.0;
  st.converged = rnorm <= target && std::isfinite(rnorm);
  warm_ = x_;
  update_nodes(w, h, [this, &w](int i) { w.v[i] += x_[i]; });
  return st;
}

}  // namespace harness
