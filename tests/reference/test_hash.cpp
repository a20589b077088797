// Spatial hashing (core/collision/detectors/hash.hpp) against CGAL's exact inside test: on 1,200
// seeded random poses of closed meshes (convex and not), at cell sizes from half to four times
// the mean edge, the inside sets are equal and the nearest triangles are nearest.
#include "core/scene/scene.hpp"
#include "core/collision/detectors/hash.hpp"
#include "reference/reference.hpp"
#include "tests/reference/reference_test_worlds.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <random>

using namespace harness;
using namespace harness::reftest;

namespace {

// A closed, non-convex (star-shaped) surface: an icosphere whose radius varies with direction.
Surface dented_sphere(const Vec3& c, double r, int sub) {
  Surface s = icosphere(Vec3::Zero(), 1.0, sub);
  for (Vec3& v : s.V) {
    const double th = std::atan2(v.y(), v.x()), ph = std::acos(std::clamp(v.z(), -1.0, 1.0));
    v = c + r * (1.0 + 0.35 * std::sin(3.0 * th) * std::sin(2.0 * ph)) * v;
  }
  return s;
}

Surface posed(Surface s, const Eigen::Matrix3d& R, const Vec3& t) {
  for (Vec3& v : s.V) v = R * v + t;
  return s;
}

}  // namespace

TEST_CASE("spatial hashing: inside sets equal CGAL's on 1200 random poses", "[hash][cgal]") {
  std::mt19937 rng(2024);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const Surface shapes[] = {icosphere(Vec3::Zero(), 0.02, 2), dented_sphere(Vec3::Zero(), 0.02, 3),
                            box_surface(Vec3(-0.03, -0.01, -0.005), Vec3(0.03, 0.01, 0.005), Vec3i(6, 2, 1))};
  const double factors[] = {0.5, 1.0, 2.0, 4.0};
  long long points = 0, inside = 0;
  for (int pose = 0; pose < 1200; ++pose) {
    const Surface& shape = shapes[pose % 3];
    World w;
    ContactSpec pair = contact_spec_defaults();
    pair.host = add_body(w, "host", posed(shape, random_rotation(rng), 0.01 * Vec3(u(rng), u(rng), u(rng))));
    Points cloud_pts;
    for (int i = 0; i < 150; ++i) cloud_pts.push_back(0.04 * Vec3(u(rng), u(rng), u(rng)));
    pair.guest = harness::test::add_body(w, "guest", harness::test::cloud(cloud_pts));
    // Mean edge of this host.
    double edge = 0.0;
    const Body& h = w.bodies[pair.host];
    for (const Tri& t : h.faces)
      for (int k = 0; k < 3; ++k) edge += (w.x[h.begin + t[k]] - w.x[h.begin + t[(k + 1) % 3]]).norm();
    edge /= 3.0 * h.faces.size();
    pair.cell_size = factors[(pose / 3) % 4] * edge;
    HashDetector hash;
    hash.initialize(w, pair);
    std::vector<Contact> contacts;
    hash.detect(w, contacts);
    CgalSurface cg;
    cg.set_topology(h.n_surface, h.faces);
    cg.update(&w.x[h.begin]);
    std::vector<std::uint8_t> by_hash(cloud_pts.size(), 0);
    for (const Contact& c : contacts) by_hash[c.guest - w.bodies[pair.guest].begin] = 1;
    const Body& g = w.bodies[pair.guest];
    for (int i = g.begin; i < g.end; ++i) {
      const bool exact = cg.strictly_inside(w.x[i]);
      INFO("pose " << pose << " point " << i - g.begin << " cell " << pair.cell_size);
      REQUIRE(static_cast<bool>(by_hash[i - g.begin]) == exact);
      ++points;
      inside += exact;
    }
    // The contact's triangle is a nearest one: its distance is CGAL's distance to the surface.
    for (const Contact& c : contacts) {
      ContactPoint cp;
      REQUIRE(hash.contact_point(w, c, cp));
      CHECK(cp.depth * cp.depth == Approx(cg.squared_distance(w.x[c.guest])).epsilon(1e-9).margin(1e-18));
    }
  }
  WARN("hash against CGAL: " << points << " points, " << inside << " inside");
  CHECK(inside > points / 20);  // the test sees plenty of both
  CHECK(inside < points - points / 20);
}

TEST_CASE("spatial hashing: rays through edges and vertices along every axis and direction", "[hash]") {
  // An axis-aligned box meshed 4 x 4 x 4 per face, and query points on the lattice of its vertices
  // and edge midpoints: each point's ray (the shortest way out: any of the six directions) runs
  // exactly along triangles' edges and through their vertices. The box is analytic: strictly
  // inside when every coordinate is strictly within it; on a face, edge or corner: outside.
  World w;
  ContactSpec pair = contact_spec_defaults();
  const Vec3 lo(-0.0625, -0.03125, -0.015625), hi = -lo;  // binary fractions: every lattice point exact
  pair.host = add_body(w, "host", box_surface(lo, hi, Vec3i(4, 4, 4)));
  Points pts;
  const Vec3 step = (hi - lo) / 8.0;
  for (int i = -1; i <= 9; ++i)
    for (int j = -1; j <= 9; ++j)
      for (int k = -1; k <= 9; ++k) pts.push_back(lo + Vec3(i * step.x(), j * step.y(), k * step.z()));
  pair.guest = harness::test::add_body(w, "guest", harness::test::cloud(pts));
  for (double cell : {0.0, 0.004, 0.011}) {
    pair.cell_size = cell;
    HashDetector hash;
    hash.initialize(w, pair);
    std::vector<Contact> contacts;
    hash.detect(w, contacts);
    std::vector<std::uint8_t> got(pts.size(), 0);
    for (const Contact& c : contacts) got[c.guest - w.bodies[pair.guest].begin] = 1;
    int inside = 0;
    for (std::size_t n = 0; n < pts.size(); ++n) {
      const Vec3& p = pts[n];
      const bool truth = (p.array() > lo.array()).all() && (p.array() < hi.array()).all();
      INFO("cell " << cell << " point " << p.transpose());
      REQUIRE(static_cast<bool>(got[n]) == truth);
      inside += truth;
    }
    CHECK(inside == 7 * 7 * 7);
  }
}
