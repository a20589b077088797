// The CGAL ground truth of a pair (ReferenceMeasurer with solver cgal) on analytic
// configurations: two icospheres, a cube in a layer; bookkeeping of tp/fp/fn; no stale trees.
#include "core/scene/scene.hpp"
#include "reference/reference.hpp"
#include "tests/reference/reference_test_worlds.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

using namespace harness;
using namespace harness::reftest;

namespace {

ReferenceSpec cgal_only() {
  ReferenceSpec s = reference_spec_defaults();
  s.cgal = true;
  return s;
}

ContactSpec pair_of(int host, int guest) {
  ContactSpec p = contact_spec_defaults();
  p.host = host;
  p.guest = guest;
  return p;
}

// Interior nodes for a sphere: lattice points (spacing h) strictly within radius 0.9 r.
Points interior_nodes(const Vec3& c, double r, double h) {
  Points p;
  const int n = static_cast<int>(r / h);
  for (int i = -n; i <= n; ++i)
    for (int j = -n; j <= n; ++j)
      for (int k = -n; k <= n; ++k) {
        const Vec3 q = c + h * Vec3(i, j, k);
        if ((q - c).norm() < 0.9 * r) p.push_back(q);
      }
  return p;
}

}  // namespace

TEST_CASE("two icospheres: truly penetrating nodes match the analytic spheres", "[reference][cgal]") {
  const double r = 1.0;
  const int sub = 3;
  // centre distance d: deep (a centre inside the other sphere), overlapping, shallow, apart
  const double d = GENERATE(0.5, 1.5, 1.8, 1.95, 2.2);
  const bool volumetric = GENERATE(false, true);  // guest with interior nodes too
  const Vec3 ca(0.1, -0.2, 0.3);
  const Vec3 dir = Vec3(1.0, 0.37, -0.21).normalized();  // not along a symmetry axis
  const Vec3 cb = ca + d * dir;
  CAPTURE(d, volumetric);

  Surface A = icosphere(ca, r, sub);
  if (volumetric)
    for (const Vec3& q : interior_nodes(ca, r, 0.2)) A.V.push_back(q);
  const Surface B = icosphere(cb, r, sub);
  World w;
  const int host = add_body(w, "B", B);
  const int guest = add_body(w, "A", A);
  ReferenceMeasurer m(w, pair_of(host, guest), cgal_only());
  Measurement out;
  m.measure(w, pair_of(host, guest), {}, out);
  REQUIRE(out.has_cgal);
  REQUIRE_FALSE(out.has_fcl);

  // Band of the discretisation: each polyhedron lies between its nearest face plane and the
  // sphere of radius r. Outside the band the classification must be the analytic one.
  const double inner = min_plane_distance(B, cb);  // the same for A about ca
  REQUIRE(inner < r);
  REQUIRE(inner > r * std::cos(max_edge_angle(B, cb)));
  int sure = 0, band = 0;
  double analytic_nodes = 0.0;  // deepest node by the analytic spheres
  const auto& flags = m.guest_penetrating();
  for (int i = 0; i < static_cast<int>(A.V.size()); ++i) {
    const double rho = (A.V[i] - cb).norm();
    if (rho < r) analytic_nodes = std::max(analytic_nodes, r - rho);
    if (rho < inner) {
      ++sure;
      CHECK(flags[i] == 1);
    } else if (rho > r) {
      CHECK(flags[i] == 0);
    } else {
      ++band;
    }
  }
  CHECK(out.true_pen_guest >= sure);
  CHECK(out.true_pen_guest <= sure + band);
  CHECK(band <= static_cast<int>(A.V.size()) / 10);  // the band is thin

  // Host nodes (B's surface) against A: the same with the roles swapped.
  int sure_h = 0, band_h = 0;
  for (const Vec3& q : B.V) {
    const double rho = (q - ca).norm();
    if (rho < r) analytic_nodes = std::max(analytic_nodes, r - rho);
    if (rho < inner) ++sure_h;
    else if (rho <= r) ++band_h;
  }
  CHECK(out.true_pen_host >= sure_h);
  CHECK(out.true_pen_host <= sure_h + band_h);

  if (d < 2 * r) {
    // Per node: the distance to a polyhedron inscribed in the sphere is at most the distance to
    // the sphere, and at least that less the polyhedron's gap r - inner.
    CAPTURE(analytic_nodes, out.max_depth);
    CHECK(out.max_depth <= analytic_nodes + 1e-12);
    CHECK(out.max_depth >= analytic_nodes - (r - inner) - 1e-12);
    if (!volumetric) {
      // Against the continuous spheres: depth r - |r - d|, found by surface vertices up to the
      // angular sampling alpha (second order where the depth is stationary).
      const double analytic = r - std::fabs(r - d);
      const double alpha = max_edge_angle(B, cb);
      const double sampling =
          std::sqrt((r - d) * (r - d) + 2 * r * d * (1 - std::cos(alpha))) - std::fabs(r - d);
      CAPTURE(analytic, sampling);
      CHECK(out.max_depth <= analytic + 1e-12);
      CHECK(out.max_depth >= analytic - sampling - (r - inner) - 1e-12);
    }
    CHECK(out.mean_depth > 0.0);
    CHECK(out.mean_depth <= out.max_depth);
    CHECK(out.surfaces_intersect);
  } else {
    CHECK(out.true_pen_guest == 0);
    CHECK(out.true_pen_host == 0);
    CHECK(out.max_depth == 0.0);
    CHECK(out.mean_depth == 0.0);
    CHECK_FALSE(out.surfaces_intersect);
  }
}

TEST_CASE("a sphere inside a sphere: containment without surface contact", "[reference][cgal]") {
  World w;
  const int host = add_body(w, "big", icosphere(Vec3::Zero(), 1.0, 2));
  const Surface small = icosphere(Vec3(0.1, 0, 0), 0.3, 1);
  const int guest = add_body(w, "small", small);
  ReferenceSpec spec = cgal_only();
  spec.fcl = true;
  ReferenceMeasurer m(w, pair_of(host, guest), spec);
  Measurement out;
  m.measure(w, pair_of(host, guest), {}, out);
  CHECK(out.true_pen_guest == small.n_surface);
  CHECK(out.true_pen_host == 0);
  CHECK(out.surfaces_intersect);  // bounded sides overlap
  CHECK(out.fcl_pairs == 0);      // FCL sees no triangle pair
  CHECK_FALSE(surfaces_intersect(m.cgal_surface(false), m.cgal_surface(true), false));
}

namespace {
// Cube [0,1]^3 (4 cells a side) as guest, sunk 0.25 into the layer [-1,2]x[-1,2]x[-0.5,0.25]
// (cells 0.5 x 0.5 x 0.25) as host. Exactly representable coordinates throughout.
struct CubeInLayer {
  World w;
  int host = -1, guest = -1;
  CubeInLayer() {
    host = add_body(w, "layer", box_surface(Vec3(-1, -1, -0.5), Vec3(2, 2, 0.25), Vec3i(6, 6, 3)));
    guest = add_body(w, "cube", box_surface(Vec3(0, 0, 0), Vec3(1, 1, 1), Vec3i(4, 4, 4)));
  }
  ContactSpec pair() const { return pair_of(host, guest); }
  int guest_node(const Vec3& p) const {
    const Body& b = w.bodies[guest];
    for (int i = b.begin; i < b.end; ++i)
      if ((w.x[i] - p).norm() < 1e-12) return i;
    return -1;
  }
};
}  // namespace

TEST_CASE("cube sunk into a layer: exact counts, boundary vertices outside, depth", "[reference][cgal]") {
  CubeInLayer s;
  ReferenceSpec spec = cgal_only();
  spec.volume = true;
  spec.fcl = true;
  spec.ccd = true;
  ReferenceMeasurer m(s.w, s.pair(), spec);
  Measurement out;
  m.measure(s.w, s.pair(), {}, out);
  // The 25 vertices of the cube's bottom face are inside; the ring at z = 0.25 lies on the
  // layer's top face and counts as outside.
  CHECK(out.true_pen_guest == 25);
  // One layer vertex, (0.5, 0.5, 0.25), is strictly inside the cube; (0, y, 0.25) and (1, y, 0.25)
  // lie on its faces.
  CHECK(out.true_pen_host == 1);
  CHECK(out.max_depth == Approx(0.25).margin(1e-12));
  CHECK(out.mean_depth == Approx(0.25).margin(1e-12));
  CHECK(out.surfaces_intersect);
  REQUIRE(out.has_volume);
  CHECK(out.penetration_volume == Approx(0.25).margin(1e-9));
  CHECK(out.has_fcl);
  CHECK(out.fcl_pairs > 0);
  CHECK(out.fcl_max_depth > 0.0);
  REQUIRE(out.has_ccd);
  CHECK(out.ccd_distance == Approx(-0.25).margin(1e-6));  // hulls: the boxes themselves
  CHECK(out.t_cgal_us > 0.0);
  CHECK(out.t_fcl_us > 0.0);
  CHECK(out.t_ccd_us > 0.0);
}

TEST_CASE("tp, fp and fn of a hand-made detected list", "[reference][cgal]") {
  CubeInLayer s;
  ReferenceMeasurer m(s.w, s.pair(), cgal_only());
  const int in = s.guest_node(Vec3(0.25, 0.5, 0.0));      // bottom face: truly penetrating
  const int in2 = s.guest_node(Vec3(1.0, 1.0, 0.0));      // bottom corner: truly penetrating
  const int ring = s.guest_node(Vec3(0.0, 0.5, 0.25));    // on the layer's surface: not
  const int top = s.guest_node(Vec3(0.5, 0.5, 1.0));      // far above: not
  REQUIRE(in >= 0);
  REQUIRE(in2 >= 0);
  REQUIRE(ring >= 0);
  REQUIRE(top >= 0);
  const int host_node = s.w.bodies[s.host].begin;  // not a guest node at all
  const std::vector<Contact> detected = {{in, 7}, {ring, 0}, {in, 3}, {top, 1}, {in2, 0}, {host_node, 0}, {ring, 2}};
  Measurement out;
  m.measure(s.w, s.pair(), detected, out);
  CHECK(out.true_pen_guest == 25);
  CHECK(out.tp == 2);  // `in` twice counts once
  CHECK(out.fp == 3);  // ring (once), top, the host node
  CHECK(out.fn == 23);
  // A second call counts afresh.
  m.measure(s.w, s.pair(), {}, out);
  CHECK(out.tp == 0);
  CHECK(out.fp == 0);
  CHECK(out.fn == 25);
}

TEST_CASE("results follow the bodies: no stale tree", "[reference][cgal][fcl]") {
  CubeInLayer s;
  ReferenceSpec spec = cgal_only();
  spec.fcl = true;
  ReferenceMeasurer m(s.w, s.pair(), spec);
  Measurement out;
  m.measure(s.w, s.pair(), {}, out);
  REQUIRE(out.true_pen_guest == 25);
  const int pairs0 = out.fcl_pairs;
  REQUIRE(pairs0 > 0);

  // Both bodies far away, same relative pose: nothing changes.
  translate_body(s.w, s.host, Vec3(10, -3, 7));
  translate_body(s.w, s.guest, Vec3(10, -3, 7));
  m.measure(s.w, s.pair(), {}, out);
  CHECK(out.true_pen_guest == 25);
  CHECK(out.true_pen_host == 1);
  CHECK(out.max_depth == Approx(0.25).margin(1e-12));
  CHECK(out.fcl_pairs == pairs0);

  // Cube lifted clear of the layer.
  translate_body(s.w, s.guest, Vec3(0, 0, 0.5));
  m.measure(s.w, s.pair(), {}, out);
  CHECK(out.true_pen_guest == 0);
  CHECK(out.true_pen_host == 0);
  CHECK_FALSE(out.surfaces_intersect);
  CHECK(out.fcl_pairs == 0);

  // Cube pushed down to z in [-0.375, 0.625]: its bottom face (z = -0.375) and the rings at
  // z = -0.125 and 0.125 are inside the layer; of the layer, still (0.5, 0.5, 0.25) alone is
  // inside the cube. Deepest: the ring at z = -0.125 and that layer vertex, 0.375.
  translate_body(s.w, s.guest, Vec3(0, 0, -0.875));
  m.measure(s.w, s.pair(), {}, out);
  CHECK(out.true_pen_guest == 25 + 16 + 16);
  CHECK(out.true_pen_host == 1);
  CHECK(out.max_depth == Approx(0.375).margin(1e-12));
  CHECK(out.fcl_pairs > 0);
}

TEST_CASE("inside_surface: strict inside, boundary outside", "[reference][cgal]") {
  const Surface box = box_surface(Vec3(0, 0, 0), Vec3(1, 1, 1), Vec3i(2, 2, 2));
  const Points q = {{0.5, 0.5, 0.5}, {0.0, 0.5, 0.5}, {1e-9, 0.5, 0.5}, {-1e-9, 0.5, 0.5},
                    {1, 1, 1},       {0.5, 0.5, 2.0}};
  const std::vector<bool> in = inside_surface(box.V, box.F, q);
  CHECK(in == std::vector<bool>{true, false, true, false, false, false});
}

TEST_CASE("reference_versions names FCL and CGAL", "[reference]") {
  CHECK(reference_versions() == "FCL 0.7.0, CGAL 5.5.1");
  const auto v = reference_version_map();
  CHECK(v.at("FCL") == "0.7.0");
  CHECK(v.at("CGAL") == "5.5.1");
}

// Cost of each reference per measured step on two overlapping icospheres. Hidden from the
// default run: `harness_reference_tests "[.bench]"`.
TEST_CASE("bench: reference cost per measured step", "[.bench][cgal][fcl]") {
  std::printf("%5s %7s %9s %9s %9s %9s %9s\n", "sub", "nodes", "cgal_us", "fcl_us", "ccd_us",
              "volume_us", "pen");
  for (int sub = 3; sub <= 5; ++sub) {
    World w;
    const int host = add_body(w, "B", icosphere(Vec3(1.6, 0.05, -0.03), 1.0, sub));
    const int guest = add_body(w, "A", icosphere(Vec3::Zero(), 1.0, sub));
    ReferenceSpec spec = reference_spec_defaults();
    spec.cgal = spec.fcl = spec.ccd = true;
    spec.volume = sub <= 4;
    ReferenceMeasurer m(w, pair_of(host, guest), spec);
    Measurement out, sum;
    const int steps = 5;
    for (int s = 0; s < steps; ++s) {
      translate_body(w, guest, Vec3(0.001, 0, 0));  // moving: trees must follow
      m.measure(w, pair_of(host, guest), {}, out);
      sum.t_cgal_us += out.t_cgal_us / steps;
      sum.t_fcl_us += out.t_fcl_us / steps;
      sum.t_ccd_us += out.t_ccd_us / steps;
      sum.t_volume_us += out.t_volume_us / steps;
    }
    std::printf("%5d %7d %9.0f %9.0f %9.0f %9.0f %9d\n", sub, w.num_nodes(), sum.t_cgal_us, sum.t_fcl_us,
                sum.t_ccd_us, sum.t_volume_us, out.true_pen_guest + out.true_pen_host);
  }
}

TEST_CASE("collapsed triangles: distances without CGAL's projection, no abort", "[reference][cgal]") {
  // Collapse triangles of an icosphere: a vertex moved onto the midpoint of the opposite edge of
  // one of its triangles (that triangle becomes a segment; CGAL's projection on it is NaN and
  // the exact fallback of the next comparison would abort inside GMP).
  Surface s = icosphere(Vec3::Zero(), 1.0, 2);
  int collapsed = 0;
  std::vector<bool> moved(s.V.size(), false);
  for (const Tri& t : s.F) {
    if (collapsed == 6) break;
    if (moved[t[0]] || moved[t[1]] || moved[t[2]]) continue;
    s.V[t[0]] = 0.5 * (s.V[t[1]] + s.V[t[2]]);
    moved[t[0]] = moved[t[1]] = moved[t[2]] = true;
    ++collapsed;
  }
  CgalSurface surface;
  surface.set_topology(s.n_surface, s.F);
  surface.update(s.V.data());
  CHECK(surface.num_degenerate_faces() >= collapsed);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.2, 1.2);
  for (int q = 0; q < 300; ++q) {
    const Vec3 p(u(rng), u(rng), u(rng));
    double best = 1e300;
    for (const Tri& t : s.F) {
      const Vec3 &a = s.V[t[0]], &b = s.V[t[1]], &c = s.V[t[2]];
      if (is_degenerate(a, b, c)) {
        for (const Vec3& e : {closest_on_segment(p, a, b), closest_on_segment(p, b, c), closest_on_segment(p, c, a)})
          best = std::min(best, (e - p).squaredNorm());
      } else {
        best = std::min(best, (closest_on_triangle(p, a, b, c) - p).squaredNorm());
      }
    }
    CHECK(surface.squared_distance(p) == Approx(best).epsilon(1e-9).margin(1e-15));
    Vec3 closest;
    const int f = surface.closest_face(p, &closest);
    REQUIRE(f >= 0);
    CHECK((closest - p).squaredNorm() == Approx(best).epsilon(1e-9).margin(1e-15));
    (void)surface.side(p);  // predicates only: fine on collapsed faces
  }
  // The measurer survives it too (volume refused: corefinement needs proper faces).
  World w;
  ContactSpec pair = pair_of(add_body(w, "collapsed", s), -1);
  Surface other = icosphere(Vec3(0.9, 0.2, 0.1), 0.5, 2);
  pair.guest = add_body(w, "other", other);
  ReferenceSpec spec = cgal_only();
  spec.volume = spec.fcl = spec.ccd = true;
  ReferenceMeasurer m(w, pair, spec);
  Measurement out;
  m.measure(w, pair, {}, out);
  CHECK(out.has_cgal);
  CHECK(out.true_pen_guest > 0);
  CHECK_FALSE(out.has_volume);
}

// Tunnelled nodes (Measurement::tunnelled_guest / host, ReferenceMeasurer's Passages): a small
// cube (the guest) moved by hand against a thin slab (the host) between measurements. Through the
// slab in one jump or in steps (inside on a measured step), it counts; back out where it came in,
// around the slab to its far side, or through and back again, it does not.
TEST_CASE("tunnelled: through counts, pushed back, around and back again do not", "[reference][cgal]") {
  // Host: a slab 1 x 1 x 0.2 (z from 0 to 0.2); guest: a cube of side 0.05 above its middle.
  const Surface slab = box_surface(Vec3(0, 0, 0), Vec3(1, 1, 0.2), Vec3i(2, 2, 1));
  const Surface cube = box_surface(Vec3(0.475, 0.475, 0.3), Vec3(0.525, 0.525, 0.35), Vec3i(1, 1, 1));
  World w;
  const int host = add_body(w, "slab", slab);
  const int guest = add_body(w, "cube", cube);
  const ContactSpec pair = pair_of(host, guest);
  ReferenceMeasurer m(w, pair, cgal_only());
  Measurement out;
  auto move_to = [&](const Vec3& d) { translate_body(w, guest, d); m.measure(w, pair, {}, out); return out.tunnelled_guest; };
  REQUIRE(move_to(Vec3::Zero()) == 0);  // the first measurement only starts the record
  const int n = static_cast<int>(cube.V.size());
  REQUIRE(n == 8);

  SECTION("through in one jump between measurements") {
    CHECK(move_to(Vec3(0, 0, -0.6)) == n);  // from z 0.3 to -0.3: every vertex crossed both faces
    CHECK(out.tunnelled_host == 0);
    CHECK(move_to(Vec3(0, 0, 0.6)) == 0);   // and back through: on its side again
  }
  SECTION("through in steps, seen inside on the way") {
    CHECK(move_to(Vec3(0, 0, -0.22)) == 0);  // z 0.08 to 0.13: wholly inside
    CHECK(out.true_pen_guest == n);
    CHECK(move_to(Vec3(0, 0, -0.1)) == 4);   // the bottom four out through the slab's bottom
    CHECK(move_to(Vec3(0, 0, -0.1)) == n);   // all of them
  }
  SECTION("in and pushed back out where it came in") {
    CHECK(move_to(Vec3(0, 0, -0.12)) == 0);  // the bottom four inside (z 0.18)
    CHECK(out.true_pen_guest > 0);
    CHECK(move_to(Vec3(0, 0, 0.12)) == 0);
  }
  SECTION("around the slab's edge to its far side: never inside, never through") {
    CHECK(move_to(Vec3(0.7, 0, 0)) == 0);   // beside the slab (x beyond 1)
    CHECK(move_to(Vec3(0, 0, -0.6)) == 0);  // down past its side
    CHECK(move_to(Vec3(-0.7, 0, 0)) == 0);  // under its middle: beyond the far side, in its shadow
    CHECK(out.true_pen_guest == 0);
  }
  SECTION("in through the top, out through a side: not through") {
    CHECK(move_to(Vec3(0, 0, -0.2)) == 0);  // wholly inside
    CHECK(out.true_pen_guest == n);
    CHECK(move_to(Vec3(0.6, 0, 0)) == 0);   // slid sideways out of the slab (x beyond 1)
    CHECK(out.true_pen_guest == 0);
  }
}

// CgalSurface::update keeps its AABB tree (boxes grown by a margin) while no vertex has moved
// farther than the margin since the tree was built: every query must then equal that of a surface
// built afresh on the same points, and a larger move must rebuild it.
TEST_CASE("CGAL surface: a kept tree answers as a fresh one, and is rebuilt past its margin", "[reference][cgal]") {
  const Surface ball = icosphere(Vec3::Zero(), 1.0, 3);
  CgalSurface kept;
  kept.set_topology(ball.n_surface, ball.F);
  kept.update(ball.V.data());
  REQUIRE(kept.tree_rebuilds() == 1);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  // Mean edge of this icosphere ~0.1: margin ~0.025; wobble every vertex by up to 0.012 (within).
  Points moved = ball.V;
  int compared = 0, disagreements = 0;
  for (int round = 0; round < 20; ++round) {
    for (int i = 0; i < ball.n_surface; ++i) moved[i] = ball.V[i] + 0.007 * Vec3(u(rng), u(rng), u(rng));
    kept.update(moved.data());
    CgalSurface fresh;
    fresh.set_topology(ball.n_surface, ball.F);
    fresh.update(moved.data());
    for (int q = 0; q < 200; ++q) {
      const Vec3 p = 1.2 * Vec3(u(rng), u(rng), u(rng));
      disagreements += kept.side(p) != fresh.side(p);
      Vec3 a, b;
      kept.closest_face(p, &a);
      fresh.closest_face(p, &b);
      disagreements += std::fabs((a - p).norm() - (b - p).norm()) > 1e-14;
      std::vector<SurfaceCrossing> ca, cb;
      const Vec3 r = 1.2 * Vec3(u(rng), u(rng), u(rng));
      kept.crossings(p, r, ca);
      fresh.crossings(p, r, cb);
      disagreements += ca.size() != cb.size();
      ++compared;
    }
  }
  CHECK(compared == 4000);
  CHECK(disagreements == 0);
  CHECK(kept.tree_rebuilds() == 1);  // every wobble stayed within the margin: never rebuilt
  // A rigid shift of a third of the radius leaves the margin: rebuilt, and right.
  for (int i = 0; i < ball.n_surface; ++i) moved[i] = ball.V[i] + Vec3(0.33, 0, 0);
  kept.update(moved.data());
  CHECK(kept.tree_rebuilds() == 2);
  CHECK(kept.strictly_inside(Vec3(1.2, 0, 0)));
  CHECK_FALSE(kept.strictly_inside(Vec3(-0.8, 0, 0)));
}
