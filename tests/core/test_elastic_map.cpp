// The Young's-modulus mapping (core/elastic_map.hpp): under a homogeneous small strain eps the
// springs' energy sum 1/2 k (l eps_uu)^2 must equal the isotropic continuum's
// V (mu eps:eps + lambda/2 (tr eps)^2), lambda = mu = E / 2.5, exactly for box lattices (boundary
// cells included, any cell aspect), and for volume fills within their surface layer's error.
#include "core/elastic_map.hpp"
#include "core/shapes/shapes.hpp"

#include <catch2/catch.hpp>

#include <random>

using namespace harness;

namespace {

// Energy per unit E of the model's volume springs under the linear strain eps.
double spring_energy(const ShapeModel& m, const Eigen::Matrix3d& eps) {
  double e = 0.0;
  for (std::size_t s = 0; s < m.springs.size(); ++s) {
    const Vec3 d = m.nodes[m.springs[s][1]] - m.nodes[m.springs[s][0]];
    const double dl = d.dot(eps * d) / d.norm();  // l * (u . eps u)
    e += 0.5 * m.spring_kappa[s] * dl * dl;
  }
  return e;
}

double continuum_energy(double volume, const Eigen::Matrix3d& eps) {
  const double mu = kShearOverYoung, lambda = mu;  // Poisson's ratio 1/4
  return volume * (mu * (eps.array() * eps.array()).sum() + 0.5 * lambda * eps.trace() * eps.trace());
}

Eigen::Matrix3d random_strain(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1e-3, 1e-3);
  Eigen::Matrix3d e;
  for (int i = 0; i < 3; ++i)
    for (int j = i; j < 3; ++j) e(i, j) = e(j, i) = u(rng);
  return e;
}

}  // namespace

TEST_CASE("isotropic cell constants: the cube's closed form, positive for moderate aspect", "[elastic]") {
  const CellSprings c = isotropic_cell(Vec3::Constant(0.01));
  const double mu = kShearOverYoung * 0.01;  // per unit E, times h
  for (int a = 0; a < 3; ++a) {
    CHECK(c.edge[a] == Approx(1.5 * mu));
    CHECK(c.face[a] == Approx(0.5 * mu));
  }
  CHECK(c.body == Approx(0.375 * mu));
  double dev = 1.0;
  const CellSprings flat = isotropic_cell(Vec3(0.005, 0.005, 0.004), &dev);  // implant tissue cells
  for (int a = 0; a < 3; ++a) CHECK(flat.edge[a] > 0.0);
  CHECK(dev < 1e-12);
  // A long cell cannot be isotropic: the nearest nonnegative constants, and the deviation says so.
  const CellSprings longer = isotropic_cell(Vec3(0.01, 0.02, 0.01), &dev);
  CHECK(dev > 0.1);
  for (double k : {longer.edge[0], longer.edge[1], longer.edge[2], longer.face[0], longer.face[1], longer.face[2], longer.body})
    CHECK(k >= 0.0);
}

TEST_CASE("box lattices store the isotropic energy exactly under any homogeneous strain", "[elastic]") {
  std::mt19937 rng(5);
  const std::pair<Vec3i, Vec3> cases[] = {{Vec3i(3, 3, 3), Vec3(0.03, 0.03, 0.03)},
                                          {Vec3i(5, 4, 4), Vec3(0.05, 0.044, 0.042)},
                                          {Vec3i(32, 32, 3), Vec3(0.16, 0.16, 0.012)},
                                          {Vec3i(20, 20, 4), Vec3(0.1, 0.1, 0.02)}};
  for (const auto& [cells, hi] : cases) {
    const ShapeModel m = make_box(Vec3::Zero(), hi, cells);
    REQUIRE(m.spring_kappa.size() == m.springs.size());
    CHECK(m.kappa_anisotropy < 1e-12);
    for (int t = 0; t < 20; ++t) {
      const Eigen::Matrix3d eps = random_strain(rng);
      INFO("cells " << cells.transpose());
      CHECK(spring_energy(m, eps) == Approx(continuum_energy(m.volume, eps)).epsilon(1e-10));
    }
  }
}

TEST_CASE("volume fills approach the isotropic energy as the mesh is refined", "[elastic]") {
  std::mt19937 rng(6);
  double last_error = 1e9;
  for (int subdivisions : {2, 3, 4}) {
    const ShapeModel m = make_sphere(Vec3::Zero(), 0.02, subdivisions, Fill::volume);
    double worst = 0.0;
    for (int t = 0; t < 20; ++t) {
      const Eigen::Matrix3d eps = random_strain(rng);
      const double want = continuum_energy(m.volume, eps);
      worst = std::max(worst, std::fabs(spring_energy(m, eps) - want) / want);
    }
    INFO("subdivisions " << subdivisions << ": worst relative energy error " << worst);
    CHECK(worst < 0.35);
    CHECK(worst < last_error * 1.05);
    last_error = worst;
  }
}

TEST_CASE("shells: edge springs carry E t sum(A)/l^2, bending springs E t^3 / (4 l^2)", "[elastic]") {
  const ShapeModel m = make_sphere(Vec3::Zero(), 0.05, 3, Fill::shell);
  REQUIRE(m.spring_role.size() == m.springs.size());
  int membrane = 0, bending = 0;
  double area_sum = 0.0;
  for (std::size_t s = 0; s < m.springs.size(); ++s) {
    const double l2 = (m.nodes[m.springs[s][0]] - m.nodes[m.springs[s][1]]).squaredNorm();
    if (m.spring_role[s] == SpringRole::membrane) {
      ++membrane;
      area_sum += m.spring_kappa[s] * l2;
    } else {
      ++bending;
      CHECK(m.spring_kappa[s] * 4.0 * l2 == Approx(1.0));
    }
  }
  double area = 0.0;
  for (const Tri& t : m.faces)
    area += 0.5 * (m.nodes[t[1]] - m.nodes[t[0]]).cross(m.nodes[t[2]] - m.nodes[t[0]]).norm();
  CHECK(membrane == bending);                // one bending spring across every edge
  CHECK(area_sum == Approx(3.0 * area));  // every triangle counted once by each of its three edges
}
