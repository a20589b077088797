// The layered depth images' shared volume and its gradient (core/collision/intersection_volume.hpp)
// against configurations whose answer is known: two boxes (exact), an icosahedron inside a box (its
// volume), disjoint bodies (zero); the gradient against finite differences along each image's axis
// and its sum (zero: a translation changes no volume).
#include "core/collision/intersection_volume.hpp"
#include "tests/core/collision/collision_test_worlds.hpp"

#include <catch2/catch.hpp>

#include <cmath>

using namespace harness;
using namespace harness::test;

namespace {

// The volume of the icosahedron inscribed in a sphere of radius r: (5/12)(3 + sqrt 5) a^3 with
// edge a = r / sin(2 pi / 5).
double icosahedron_volume(double r) {
  const double a = r / std::sin(2.0 * std::acos(-1.0) / 5.0);
  return 5.0 / 12.0 * (3.0 + std::sqrt(5.0)) * a * a * a;
}

}  // namespace

TEST_CASE("LDI volume of two overlapping boxes is their overlap's, exactly where the pixels tile it",
          "[collision][volume]") {
  World w;
  const int a = add_body(w, "a", box_lattice(Vec3(0, 0, 0), Vec3(0.04, 0.03, 0.02), Vec3i(4, 3, 2)));
  const int b = add_body(w, "b", box_lattice(Vec3(0.01, 0.01, 0.005), Vec3(0.06, 0.05, 0.05), Vec3i(5, 4, 4)));
  // overlap 0.03 x 0.02 x 0.015; a pixel of 2.5 mm tiles every face of it
  const IntersectionVolume v = intersection_volume(w, w.x, a, b, 0.0025);
  const double exact = 0.03 * 0.02 * 0.015;
  for (double vk : v.per_axis) CHECK(vk == Approx(exact).epsilon(1e-12));
  CHECK(v.volume == Approx(exact).epsilon(1e-12));
  // a pixel that does not tile it: the overlap sampled at the pixel centres, still within a pixel
  const IntersectionVolume c = intersection_volume(w, w.x, a, b, 0.0023);
  CHECK(c.volume == Approx(exact).epsilon(0.2));
  // apart: nothing shared
  for (Vec3& p : w.x) p.x() += (&p - &w.x[0]) >= w.bodies[b].begin ? 0.1 : 0.0;
  const IntersectionVolume d = intersection_volume(w, w.x, a, b, 0.0025);
  CHECK(d.volume == 0.0);
  for (const Vec3& g : d.grad_a) CHECK(g.norm() == 0.0);
}

TEST_CASE("LDI volume of an icosahedron inside a box converges to the icosahedron's volume",
          "[collision][volume]") {
  World w;
  const double r = 0.01;
  const int ico = add_body(w, "ico", icosahedron(Vec3(0.0013, -0.0007, 0.0004), r, false));
  const int box = add_body(w, "box", box_lattice(Vec3(-0.02, -0.02, -0.02), Vec3(0.02, 0.02, 0.02), Vec3i(2, 2, 2)));
  const double exact = icosahedron_volume(r);
  double last = 1.0;
  for (double h : {r / 10.0, r / 40.0, r / 160.0}) {
    const IntersectionVolume v = intersection_volume(w, w.x, ico, box, h);
    const double err = std::abs(v.volume - exact) / exact;
    CHECK(err < last);  // converges as the pixel shrinks
    last = err;
    // each axis alone too: the shared volume is the icosahedron's from any direction
    for (double vk : v.per_axis) CHECK(std::abs(vk - exact) / exact < 0.1);
  }
  CHECK(last < 2e-3);
}

TEST_CASE("LDI gradient: finite differences along each image's axis, and a zero sum", "[collision][volume]") {
  World w;
  const int ico = add_body(w, "ico", icosahedron(Vec3(0.0013, -0.0007, 0.008), 0.01, false));
  const int box = add_body(w, "box", box_lattice(Vec3(-0.02, -0.02, -0.02), Vec3(0.02, 0.02, 0.01), Vec3i(4, 4, 3)));
  const double h = 0.0007;
  const IntersectionVolume v = intersection_volume(w, w.x, ico, box, h);
  REQUIRE(v.volume > 0.0);
  // the sum over both bodies' vertices: zero (a translation along k changes no V_k)
  Vec3 sum = Vec3::Zero();
  for (const Vec3& g : v.grad_a) sum += g;
  for (const Vec3& g : v.grad_b) sum += g;
  CHECK(sum.norm() < 1e-12 * (v.volume / h));
  // moving a vertex along k changes no pixel's coverage in image k: V_k is linear there
  const double eps = 1e-7;
  int checked = 0;
  for (int body : {ico, box}) {
    const Body& B = w.bodies[body];
    const std::vector<Vec3>& g = body == ico ? v.grad_a : v.grad_b;
    for (int s = 0; s < B.n_surface; ++s)
      for (int k = 0; k < 3; ++k) {
        Points x = w.x;
        x[B.surface_node(s)][k] += eps;
        const double up = intersection_volume(w, x, ico, box, h).per_axis[k];
        x[B.surface_node(s)][k] -= 2.0 * eps;
        const double down = intersection_volume(w, x, ico, box, h).per_axis[k];
        const double fd = (up - down) / (2.0 * eps);
        CHECK(g[s][k] == Approx(fd).margin(1e-9 * h * h / eps + 1e-12));
        checked += g[s][k] != 0.0;
      }
  }
  CHECK(checked > 10);  // the overlap's vertices carry a gradient
}
