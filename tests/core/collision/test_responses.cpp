// The responses the paper calls "restrictions" and its alternatives conserve momentum: the depth
// penalty (forces sum to zero per contact) and position-based projection (corrections shared by
// inverse mass: the centre of mass and the momentum do not move).
#include "core/collision/responses/force_rule.hpp"
#include "core/scene/scene.hpp"
#include "core/collision/collision.hpp"
#include "core/collision/responses/force_rules.hpp"
#include "core/collision/responses/projection.hpp"
#include "core/collision/intersection_volume.hpp"
#include "tests/core/collision/collision_test_worlds.hpp"

#include <catch2/catch.hpp>

#include <random>

using namespace harness;
using namespace harness::test;

namespace {

// A host lattice and a guest lattice overlapping it, random masses and velocities.
World overlapping(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  World w;
  add_body(w, "host", box_lattice(Vec3(0, 0, 0), Vec3(1, 1, 0.5), Vec3i(4, 4, 2)));
  add_body(w, "guest", box_lattice(Vec3(0.2, 0.1, 0.3) + 0.05 * Vec3(u(rng), u(rng), u(rng)),
                                   Vec3(0.8, 0.9, 0.9), Vec3i(3, 4, 3)));
  for (int i = 0; i < w.num_nodes(); ++i) {
    w.m[i] = 0.01 * (2.0 + u(rng));
    w.inv_m[i] = 1.0 / w.m[i];
    w.v[i] = 0.1 * Vec3(u(rng), u(rng), u(rng));
  }
  return w;
}

Vec3 momentum(const World& w) {
  Vec3 p = Vec3::Zero();
  for (int i = 0; i < w.num_nodes(); ++i) p += w.m[i] * w.v[i];
  return p;
}

Vec3 mass_moment(const World& w) {
  Vec3 p = Vec3::Zero();
  for (int i = 0; i < w.num_nodes(); ++i) p += w.m[i] * w.x[i];
  return p;
}

ContactSpec spec(const std::string& e, const char* r) {
  ContactSpec s = contact_spec_defaults();
  s.host = 0;
  s.guest = 1;
  s.voxel_size = 0.25;
  s.region = Region::full;
  s.eliminator = e;
  if (r == std::string("penalty")) set_force_rule(s, r, {{"stiffness", 200.0}});
  else set_force_rule(s, r);
  return s;
}

}  // namespace

TEST_CASE("the depth penalty's forces sum to zero: momentum is conserved", "[collision][responses]") {
  std::mt19937 rng(31);
  int pushing = 0;
  for (int t = 0; t < 50; ++t)
    for (const std::string e : {"line", "plane"})
      for (bool two_sided : {false, true}) {
        World w = overlapping(rng);
        ContactSpec s = spec(e, "penalty");
        s.two_sided = two_sided;
        Collision col(w, s);
        std::fill(w.f.begin(), w.f.end(), Vec3::Zero());
        const PairStep st = col.step(w, 1e-3);
        Vec3 net = Vec3::Zero();
        double total = 0.0;
        for (const Vec3& f : w.f) net += f, total += f.norm();
        CHECK(net.norm() <= 1e-12 * std::max(1.0, total));
        // No force across a gap: every push with a force has a positive depth.
        for (std::size_t i = 0; i < col.pushes().size(); ++i)
          if (col.magnitudes()[i] > 0.0) {
            CHECK(col.pushes()[i].depth > 0.0);
            ++pushing;
          }
        (void)st;
      }
  CHECK(pushing > 100);
}

TEST_CASE("projection moves penetrating nodes without moving the centre of mass or the momentum",
          "[collision][responses]") {
  std::mt19937 rng(32);
  int moved = 0;
  for (int t = 0; t < 50; ++t)
    for (bool two_sided : {false, true}) {
      World w = overlapping(rng);
      ContactSpec s = spec(std::string("projection"), "auto");
      s.two_sided = two_sided;
      Collision col(w, s);
      const Vec3 p0 = momentum(w), c0 = mass_moment(w);
      const PairStep st = col.project(w, 1e-3);
      moved += st.force > 0.0;
      CHECK((momentum(w) - p0).norm() <= 1e-12 * (1.0 + p0.norm()));
      CHECK((mass_moment(w) - c0).norm() <= 1e-12 * (1.0 + c0.norm()));
      // step() leaves a projecting pair alone (it acts after the position update).
      const Points x = w.x;
      std::fill(w.f.begin(), w.f.end(), Vec3::Zero());
      col.step(w, 1e-3);
      CHECK(w.x == x);
    }
  CHECK(moved > 50);
}

TEST_CASE("projection of one node onto a plane: the depth split by inverse mass", "[collision][responses]") {
  World w;
  add_body(w, "host", cloud({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)}));
  add_body(w, "guest", cloud({Vec3(0.25, 0.25, -0.1)}));
  w.m = {1.0, 1.0, 1.0, 3.0};
  w.inv_m = {1.0, 1.0, 1.0, 1.0 / 3.0};
  Push p;
  p.guest = 3;
  p.count = 3;
  p.hosts[0] = 0, p.hosts[1] = 1, p.hosts[2] = 2;
  p.weight[0] = 0.5, p.weight[1] = 0.25, p.weight[2] = 0.25;
  p.normal = Vec3(0, 0, 1);
  p.depth = 0.1;
  project_pushes(w, {p}, 0.01);
  // lambda = 0.1 / (1/3 + 0.25 + 0.0625 + 0.0625) = 0.1 / (17/24)
  const double lambda = 0.1 * 24.0 / 17.0;
  CHECK(w.x[3].z() == Approx(-0.1 + lambda / 3.0));
  CHECK(w.x[0].z() == Approx(-0.5 * lambda));
  CHECK(w.x[1].z() == Approx(-0.25 * lambda));
  // The guest is now on the plane through the hosts' weighted point.
  const double plane = 0.5 * w.x[0].z() + 0.25 * w.x[1].z() + 0.25 * w.x[2].z();
  CHECK(w.x[3].z() == Approx(plane));
  CHECK(w.v[3].z() == Approx(lambda / 3.0 / 0.01));
}

TEST_CASE("the volume restriction: momentum and centre of mass kept, the shared volume reduced, work booked",
          "[collision][responses][volume]") {
  std::mt19937 rng(36);
  int reduced = 0;
  for (int t = 0; t < 20; ++t) {
    World w = overlapping(rng);
    ContactSpec s = spec(std::string("volume"), "auto");
    s.volume_pixel = 0.02;
    Collision col(w, s);
    const Vec3 p0 = momentum(w), c0 = mass_moment(w);
    const double v0 = intersection_volume(w, w.x, 0, 1, s.volume_pixel).volume;
    REQUIRE(v0 > 0.0);
    std::fill(w.f.begin(), w.f.end(), Vec3::Zero());
    const Points x0 = w.x;
    const PairStep st = col.project(w, 1e-3);
    CHECK(st.force > 0.0);
    CHECK(col.volume_step().volume == Approx(v0));
    CHECK((momentum(w) - p0).norm() <= 1e-12 * (1.0 + p0.norm()));
    CHECK((mass_moment(w) - c0).norm() <= 1e-12 * (1.0 + c0.norm()));
    // interior nodes are left to their springs; only surface vertices move
    for (int b = 0; b < 2; ++b)
      for (int i = w.bodies[b].begin + w.bodies[b].n_surface; i < w.bodies[b].end; ++i) CHECK(w.x[i] == x0[i]);
    // one Newton step on V = 0: the shared volume falls (the linearisation is not exact)
    const double v1 = intersection_volume(w, w.x, 0, 1, s.volume_pixel).volume;
    CHECK(v1 < v0);
    reduced += v1 < 0.5 * v0;
    // the energy audit's contact work is the force m dx / h^2 it booked, dotted with the moves
    Points dx(w.x.size(), Vec3::Zero());
    double expect = 0.0;
    for (int i = 0; i < w.num_nodes(); ++i) {
      dx[i] = w.x[i] - x0[i];
      expect += w.f[i].dot(dx[i]);
    }
    CHECK(col.work(w, dx) == Approx(expect).epsilon(1e-12));
  }
  CHECK(reduced >= 15);
}

TEST_CASE("the volume restriction broken (pushed the wrong way) grows the shared volume; kinematic nodes stay",
          "[collision][responses][volume]") {
  std::mt19937 rng(37);
  World w = overlapping(rng);
  for (int i = w.bodies[0].begin; i < w.bodies[0].end; ++i) w.kinematic[i] = Kinematic::pinned;
  ContactSpec s = spec(std::string("volume"), "auto");
  s.volume_pixel = 0.02;
  const double v0 = intersection_volume(w, w.x, 0, 1, s.volume_pixel).volume;
  {
    World a = w;
    Collision col(a, s);
    col.project(a, 1e-3);
    for (int i = a.bodies[0].begin; i < a.bodies[0].end; ++i) CHECK(a.x[i] == w.x[i]);  // the pinned host
    CHECK(intersection_volume(a, a.x, 0, 1, s.volume_pixel).volume < v0);
  }
  s.invert_push = true;
  Collision col(w, s);
  col.project(w, 1e-3);
  CHECK(intersection_volume(w, w.x, 0, 1, s.volume_pixel).volume > v0);
}
