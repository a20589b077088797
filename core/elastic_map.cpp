#include "core/elastic_map.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <limits>
#include <vector>
#include <stdexcept>
#include <string>

namespace harness {

namespace {

// The linear map from the seven cell constants x = (edge x, y, z; face normal to x, y, z; body)
// to the six elastic constants C11, C22, C33, C23, C13, C12, each times V / mu.
Eigen::Matrix<double, 6, 7> elastic_map(const Vec3& dims) {
  const double V = dims.prod(), mu = kShearOverYoung;
  double d2[3];
  for (int a = 0; a < 3; ++a) d2[a] = dims[a] * dims[a];
  const double D2 = d2[0] + d2[1] + d2[2];
  Eigen::Matrix<double, 6, 7> A = Eigen::Matrix<double, 6, 7>::Zero();
  for (int a = 0; a < 3; ++a) {  // C_aa
    A(a, a) = d2[a];
    for (int n : {(a + 1) % 3, (a + 2) % 3}) {
      const int other = 3 - a - n;
      A(a, 3 + n) = 2.0 * d2[a] * d2[a] / (d2[a] + d2[other]);
    }
    A(a, 6) = 4.0 * d2[a] * d2[a] / D2;
  }
  for (int n = 0; n < 3; ++n) {  // C_uw of the plane normal to n
    const int u = (n + 1) % 3, w = (n + 2) % 3;
    const double P = d2[u] * d2[w];
    A(3 + n, 3 + n) = 2.0 * P / (d2[u] + d2[w]);
    A(3 + n, 6) = 4.0 * P / D2;
  }
  return A / (V * mu);
}

// Nonnegative least squares, min |A x - b| subject to x >= 0 (Lawson and Hanson 1974, ch. 23).
Eigen::Matrix<double, 7, 1> nnls(const Eigen::Matrix<double, 6, 7>& A, const Eigen::Matrix<double, 6, 1>& b) {
  using Vec7 = Eigen::Matrix<double, 7, 1>;
  Vec7 x = Vec7::Zero();
  bool passive[7] = {};
  auto solve_passive = [&]() {
    Vec7 z = Vec7::Zero();
    std::vector<int> idx;
    for (int j = 0; j < 7; ++j)
      if (passive[j]) idx.push_back(j);
    Eigen::MatrixXd Ap(6, idx.size());
    for (std::size_t c = 0; c < idx.size(); ++c) Ap.col(static_cast<Eigen::Index>(c)) = A.col(idx[c]);
    const Eigen::VectorXd zp = Ap.colPivHouseholderQr().solve(b);
    for (std::size_t c = 0; c < idx.size(); ++c) z[idx[c]] = zp[static_cast<Eigen::Index>(c)];
    return z;
  };
  for (int outer = 0; outer < 30; ++outer) {
    const Vec7 grad = A.transpose() * (b - A * x);
    int j = -1;
    for (int i = 0; i < 7; ++i)
      if (!passive[i] && grad[i] > 1e-12 && (j < 0 || grad[i] > grad[j])) j = i;
    if (j < 0) break;
    passive[j] = true;
    for (int inner = 0; inner < 30; ++inner) {
      const Vec7 z = solve_passive();
      double alpha = 1.0;
      bool feasible = true;
      for (int i = 0; i < 7; ++i)
        if (passive[i] && z[i] <= 0.0) {
          feasible = false;
          alpha = std::min(alpha, x[i] / (x[i] - z[i]));
        }
      if (feasible) {
        x = z;
        break;
      }
      x += alpha * (z - x);
      for (int i = 0; i < 7; ++i)
        if (passive[i] && x[i] <= 1e-14) passive[i] = false, x[i] = 0.0;
    }
  }
  return x;
}

CellSprings unpack(const Eigen::Matrix<double, 7, 1>& x) {
  return CellSprings{{x[0], x[1], x[2]}, {x[3], x[4], x[5]}, x[6]};
}

}  // namespace

CellSprings isotropic_cell(const Vec3& dims, double* anisotropy) {
  const Eigen::Matrix<double, 6, 7> A = elastic_map(dims);
  Eigen::Matrix<double, 6, 1> target;
  target << 3.0, 3.0, 3.0, 1.0, 1.0, 1.0;  // C_aa = 3 mu, C_ab = mu (lambda = mu)
  // Exact solutions form a line x0 + t z (z spans the null space of A). Take the point whose
  // body constant gives the body diagonals half of the largest plane C12 when that is
  // nonnegative; else the nonnegative one nearest to it; else the nonnegative least squares.
  Eigen::FullPivLU<Eigen::Matrix<double, 6, 7>> lu(A);
  const Eigen::Matrix<double, 7, 1> x0 = A.completeOrthogonalDecomposition().solve(target);
  const Eigen::Matrix<double, 7, 1> z = lu.kernel().col(0);
  double lo = -std::numeric_limits<double>::infinity(), hi = std::numeric_limits<double>::infinity();
  for (int i = 0; i < 7; ++i) {  // x0 + t z >= 0
    if (z[i] > 0.0) lo = std::max(lo, -x0[i] / z[i]);
    else if (z[i] < 0.0) hi = std::min(hi, -x0[i] / z[i]);
    else if (x0[i] < 0.0) lo = std::numeric_limits<double>::infinity();
  }
  Eigen::Matrix<double, 7, 1> x;
  if (lo <= hi && z[6] != 0.0) {
    const double plane_c12 = std::max({A(3, 6), A(4, 6), A(5, 6)});  // C12 per unit body constant
    const double want_body = 0.5 / plane_c12;
    const double t = std::clamp((want_body - x0[6]) / z[6], lo, hi);
    x = (x0 + t * z).cwiseMax(0.0);
  } else {
    x = nnls(A, target);
  }
  if (anisotropy) *anisotropy = (A * x - target).cwiseAbs().maxCoeff();
  return unpack(x);
}

}  // namespace harness
