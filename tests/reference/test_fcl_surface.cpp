// FCL on deforming surfaces: the BVH traversal against the all-pairs oracle, refit and rebuild
// policy, fcl::collide's own answer, and GJK/EPA signed distance of convex polytopes.
#include "reference/fcl_surface.hpp"
#include "reference/cgal_constructions.hpp"
#include "tests/reference/reference_test_worlds.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <stdexcept>
#include <utility>

using namespace harness;
using namespace harness::reftest;

namespace {

std::vector<std::pair<int, int>> sorted_pairs(const std::vector<TrianglePair>& p) {
  std::vector<std::pair<int, int>> s;
  for (const TrianglePair& q : p) s.emplace_back(q.a, q.b);
  std::sort(s.begin(), s.end());
  return s;
}

FclSurface make_surface(const Surface& s, FclBv bv, FclRefitPolicy policy = {}) {
  FclSurface f(bv, policy);
  f.set_topology(s.n_surface, s.F);
  f.update(s.V.data());
  return f;
}

Points rigid(const Points& V, const Eigen::Matrix3d& R, const Vec3& t) {
  Points out;
  for (const Vec3& p : V) out.push_back(R * p + t);
  return out;
}

const char* bv_name(FclBv bv) { return bv == FclBv::aabb ? "AABB" : "OBBRSS"; }

}  // namespace

TEST_CASE("FCL traversal finds exactly the all-pairs triangle intersections", "[reference][fcl]") {
  const FclBv bv = GENERATE(FclBv::aabb, FclBv::obbrss);
  CAPTURE(bv_name(bv));
  std::mt19937 rng(12345);
  const Surface a = icosphere(Vec3::Zero(), 1.0, 2);
  const Surface b0 = box_surface(Vec3(-0.6, -0.6, -0.6), Vec3(0.6, 0.6, 0.6), Vec3i(3, 3, 3));
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  int hits = 0;
  for (int trial = 0; trial < 40; ++trial) {
    Surface b = b0;
    b.V = rigid(b0.V, random_rotation(rng), Vec3(u(rng), u(rng), u(rng)));
    FclSurface fa = make_surface(a, bv), fb = make_surface(b, bv);
    std::vector<TrianglePair> fast, brute;
    intersecting_pairs(fa, fb, fast, true);
    intersecting_pairs_brute_force(fa, fb, brute);
    REQUIRE(sorted_pairs(fast) == sorted_pairs(brute));
    hits += !fast.empty();
    // fcl::collide (on OBBRSS copies): one contact per pair without contact data; with it, the
    // same deepest depth.
    FclSurface oa = make_surface(a, FclBv::obbrss), ob = make_surface(b, FclBv::obbrss);
    const FclCollideResult plain = fcl_collide(oa, ob, false);
    CHECK(plain.contacts == static_cast<int>(fast.size()));
    CHECK(plain.pairs == static_cast<int>(fast.size()));
    const FclCollideResult deep = fcl_collide(oa, ob, true);
    double max_depth = 0.0;
    int with_depth = 0;
    for (const TrianglePair& p : fast)
      if (p.has_depth) {
        max_depth = std::max(max_depth, p.depth);
        ++with_depth;
      }
    CHECK(deep.pairs == with_depth);
    CHECK(deep.max_depth == max_depth);
  }
  CHECK(hits > 5);
  CHECK(hits < 40);
  if (bv == FclBv::aabb) {
    FclSurface fa = make_surface(a, bv), fb = make_surface(b0, bv);
    CHECK_THROWS_AS(fcl_collide(fa, fb, false), std::invalid_argument);
  }
}

TEST_CASE("FCL on deforming surfaces: refitted trees stay exact; the policy rebuilds", "[reference][fcl]") {
  const FclBv bv = GENERATE(FclBv::aabb, FclBv::obbrss);
  CAPTURE(bv_name(bv));
  const Surface a = icosphere(Vec3::Zero(), 1.0, 3);
  const Surface b = icosphere(Vec3(1.7, 0.1, -0.05), 1.0, 2);
  FclRefitPolicy policy;
  policy.rebuild_every = 10;
  policy.cost_growth = 1e9;  // only the count rebuilds here
  FclSurface fa = make_surface(a, bv, policy), fb = make_surface(b, bv, policy);
  std::mt19937 rng(7);
  std::normal_distribution<double> g(0.0, 1.0);
  Points va = a.V;
  std::vector<TrianglePair> fast, brute;
  for (int step = 1; step < 30; ++step) {
    // Wobble along the normal plus a drift towards the other sphere.
    for (std::size_t i = 0; i < va.size(); ++i)
      va[i] = a.V[i] * (1.0 + 0.05 * std::sin(0.7 * step + 3.0 * a.V[i].x())) + Vec3(0.01 * step, 0, 0) +
              0.002 * Vec3(g(rng), g(rng), g(rng));
    fa.update(va.data());
    fb.update(b.V.data());
    intersecting_pairs(fa, fb, fast, false);
    intersecting_pairs_brute_force(fa, fb, brute);
    REQUIRE(sorted_pairs(fast) == sorted_pairs(brute));
  }
  CHECK(!fast.empty());
  // 30 updates: build, 10 refits, rebuild, 10 refits, rebuild, 7 refits.
  CHECK(fa.builds() == 3);
  CHECK(fa.refits() == 27);

  // A full twist about z (angle 2 pi z) keeps triangles small but tears the tree's clusters
  // apart: the refitted cost grows past the limit and the next update rebuilds, cheaper.
  FclSurface fc = make_surface(a, bv);  // default policy
  Points twisted = a.V;
  for (Vec3& p : twisted) {
    const double t = 2.0 * M_PI * p.z();
    p = Vec3(std::cos(t) * p.x() - std::sin(t) * p.y(), std::sin(t) * p.x() + std::cos(t) * p.y(), p.z());
  }
  const double cost0 = fc.tree_cost();
  fc.update(twisted.data());
  const double refitted = fc.tree_cost();
  CHECK(refitted > FclRefitPolicy{}.cost_growth * cost0);
  CHECK(fc.builds() == 1);
  fc.update(twisted.data());
  CHECK(fc.builds() == 2);
  CHECK(fc.tree_cost() < refitted);
  std::vector<TrianglePair> self_fast, self_brute;  // still exact after the rebuild
  FclSurface fd = make_surface(b, bv);
  intersecting_pairs(fc, fd, self_fast, false);
  intersecting_pairs_brute_force(fc, fd, self_brute);
  CHECK(sorted_pairs(self_fast) == sorted_pairs(self_brute));
}

TEST_CASE("GJK/EPA signed distance of convex polytopes", "[reference][ccd]") {
  const Surface cube = box_surface(Vec3(0, 0, 0), Vec3(1, 1, 1), Vec3i(1, 1, 1));
  Points V;
  std::vector<Tri> F;
  REQUIRE(convex_hull(cube.V.data(), cube.n_surface, V, F));
  CHECK(V.size() == 8);
  const double gap = GENERATE(0.5, 0.05, -0.2, -0.45);
  CAPTURE(gap);
  Points W;
  for (const Vec3& p : V) W.push_back(p + Vec3(1.0 + gap, 0.3, -0.2));
  double d = 0.0;
  REQUIRE(convex_signed_distance(V, F, W, F, d));
  CHECK(d == Approx(gap).margin(1e-6));
}

TEST_CASE("convex hull of a point cloud", "[reference][ccd]") {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Points pts;
  for (int i = 0; i < 500; ++i) pts.push_back(Vec3(u(rng), u(rng), u(rng)));
  Points V;
  std::vector<Tri> F;
  REQUIRE(convex_hull(pts.data(), static_cast<int>(pts.size()), V, F));
  CHECK(static_cast<int>(F.size()) == 2 * static_cast<int>(V.size()) - 4);  // closed, genus 0
  for (const Tri& t : F) {  // every point on the inner side of every face
    const Vec3 n = (V[t[1]] - V[t[0]]).cross(V[t[2]] - V[t[0]]);
    for (const Vec3& p : pts) CHECK(n.dot(p - V[t[0]]) <= 1e-12);
  }
  const Points flat = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {0.5, 0.5, 0}};
  CHECK_FALSE(convex_hull(flat.data(), 5, V, F));
}

// Which bounding volume refits cheapest and traverses fastest on deforming meshes. Hidden from
// the default run: `harness_reference_tests "[.bench]"`.
TEST_CASE("bench: FCL bounding volumes on deforming icospheres", "[.bench][fcl]") {
  using Clock = std::chrono::steady_clock;
  const int sub = 5, steps = 100;
  const Surface a = icosphere(Vec3::Zero(), 1.0, sub);
  const Surface b = icosphere(Vec3(1.6, 0.05, -0.03), 1.0, sub);
  std::printf("icospheres of %zu vertices, %zu triangles each, %d deforming steps\n", a.V.size(),
              a.F.size(), steps);
  std::printf("%-7s %-9s %10s %10s %12s %8s %7s %7s\n", "bv", "update", "update_us", "pairs_us",
              "collide_us", "pairs", "builds", "cost");
  for (FclBv bv : {FclBv::aabb, FclBv::obbrss})
    for (bool refit : {true, false}) {
      FclRefitPolicy policy;
      if (!refit) policy.rebuild_every = 0;  // rebuild on every update
      FclSurface fa = make_surface(a, bv, policy), fb = make_surface(b, bv, policy);
      Points va = a.V, vb = b.V;
      std::vector<TrianglePair> pairs;
      double t_update = 0, t_pairs = 0, t_collide = 0;
      long n_pairs = 0;
      for (int s = 1; s <= steps; ++s) {
        for (std::size_t i = 0; i < va.size(); ++i) {
          va[i] = a.V[i] * (1.0 + 0.04 * std::sin(0.2 * s + 4.0 * a.V[i].y()));
          vb[i] = b.V[i] + (b.V[i] - Vec3(1.6, 0.05, -0.03)) * 0.04 * std::cos(0.3 * s + 5.0 * b.V[i].z());
        }
        auto t0 = Clock::now();
        fa.update(va.data());
        fb.update(vb.data());
        auto t1 = Clock::now();
        intersecting_pairs(fa, fb, pairs, true);
        auto t2 = Clock::now();
        if (bv == FclBv::obbrss) (void)fcl_collide(fa, fb, true);  // AABB: see fcl_collide()
        auto t3 = Clock::now();
        t_update += std::chrono::duration<double, std::micro>(t1 - t0).count();
        t_pairs += std::chrono::duration<double, std::micro>(t2 - t1).count();
        t_collide += std::chrono::duration<double, std::micro>(t3 - t2).count();
        n_pairs += static_cast<long>(pairs.size());
      }
      std::printf("%-7s %-9s %10.0f %10.0f %12.0f %8ld %7d %7.1f\n", bv_name(bv), refit ? "refit" : "rebuild",
                  t_update / steps, t_pairs / steps, t_collide / steps, n_pairs / steps, fa.builds(),
                  fa.tree_cost());
    }
}
