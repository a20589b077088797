// 1,000 seeded random rigid poses of two closed meshes: CGAL's exact surface intersection and
// FCL's triangle pairs say the same yes/no; containment (no surface contact) only CGAL's
// bounded-side test catches, and every such case is checked to be containment.
#include "core/scene/scene.hpp"
#include "reference/reference.hpp"
#include "tests/reference/reference_test_worlds.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <random>

using namespace harness;
using namespace harness::reftest;

namespace {
// A bumpy, non-convex but star-shaped closed surface.
Surface bumpy_sphere(double r, int sub) {
  Surface s = icosphere(Vec3::Zero(), 1.0, sub);
  for (Vec3& p : s.V) {
    const double bump = 1.0 + 0.25 * std::sin(3.0 * std::atan2(p.y(), p.x())) * std::sin(4.0 * p.z());
    p *= r * bump;
  }
  return s;
}
}  // namespace

TEST_CASE("CGAL and FCL agree on intersection over 1000 random poses", "[reference][cgal][fcl]") {
  const Surface a0 = bumpy_sphere(0.45, 2);                                              // guest
  const Surface b0 = box_surface(Vec3(-1, -1, -1), Vec3(1, 1, 1), Vec3i(4, 4, 4));      // host
  World w;
  const int host = add_body(w, "box", b0);
  const int guest = add_body(w, "bumpy", a0);
  ContactSpec pair = contact_spec_defaults();
  pair.host = host;
  pair.guest = guest;
  ReferenceSpec spec = reference_spec_defaults();
  spec.cgal = true;
  spec.fcl = true;
  ReferenceMeasurer m(w, pair, spec);

  std::mt19937 rng(20131203);
  std::uniform_real_distribution<double> u(-1.6, 1.6);
  const Body& A = w.bodies[guest];
  const Body& B = w.bodies[host];
  int intersecting = 0, apart = 0, contained = 0, disagree = 0;
  for (int pose = 0; pose < 1000; ++pose) {
    const Eigen::Matrix3d Ra = random_rotation(rng), Rb = random_rotation(rng);
    const Vec3 ta(u(rng), u(rng), u(rng)), tb(0.1 * u(rng), 0.1 * u(rng), 0.1 * u(rng));
    for (int i = 0; i < A.size(); ++i) w.x[A.begin + i] = Ra * a0.V[i] + ta;
    for (int i = 0; i < B.size(); ++i) w.x[B.begin + i] = Rb * b0.V[i] + tb;
    Measurement out;
    m.measure(w, pair, {}, out);
    const bool cgal_surfaces = surfaces_intersect(m.cgal_surface(false), m.cgal_surface(true), false);
    const bool fcl_yes = out.fcl_pairs > 0;
    if (cgal_surfaces != fcl_yes) {
      ++disagree;
      UNSCOPED_INFO("pose " << pose << ": CGAL " << cgal_surfaces << ", FCL pairs " << out.fcl_pairs);
    }
    if (cgal_surfaces) {
      ++intersecting;
      CHECK(out.surfaces_intersect);
    } else if (out.surfaces_intersect) {
      // Containment: one body wholly inside the other, so every vertex of it is inside.
      ++contained;
      const bool a_in_b = out.true_pen_guest == A.size();
      const bool b_in_a = out.true_pen_host == B.size();
      CHECK((a_in_b || b_in_a));
      if (a_in_b) CHECK(m.cgal_surface(true).strictly_inside(w.x[A.begin]));
    } else {
      ++apart;
      CHECK(out.true_pen_guest == 0);
      CHECK(out.true_pen_host == 0);
    }
  }
  INFO("intersecting " << intersecting << ", contained " << contained << ", apart " << apart);
  CHECK(disagree == 0);
  CHECK(contained > 20);  // the cases exist and are exercised
  CHECK(intersecting > 100);
  CHECK(apart > 100);
}
