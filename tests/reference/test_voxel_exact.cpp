// The paper's grid with an exact narrow phase (core/collision/detectors/voxel_exact.hpp) against
// CGAL's exact inside test and distances: on 1,200 seeded random poses of closed meshes (convex
// icospheres and boxes, a bent non-convex shell), voxels from below L_max/sqrt(3) (no band at
// all) to several L_max, every region and margins 0 to 2, every guest node the detector reports
// within its band is strictly inside by CGAL at CGAL's depth (1e-9 m), every node CGAL finds
// inside at a depth below the node's band is reported within it (no false negatives), and the
// nodes reported beyond the band are exactly the ones counted. The band's edge: a node just
// beyond it is counted, one just within is not.
//
// The band is what makes the first two hold. Verified by breaking it in band_of (then restored):
// with band = r(x) (the L_max / sqrt(3) term dropped) pose 0 fails (a node 2.09 mm inside, band
// 2.23 mm, not found: its nearest triangle has no vertex in the block); with band = 2 v likewise;
// with band = v - L_max / 2 pose 57 fails (a node 1.89 mm inside, band 4.38 mm, found 0.016 mm
// too deep, on a farther candidate). A band of r(x) - L_max / 2 (a smaller constant than 1/sqrt(3),
// which is sufficient but not shown to be tight) survives these poses.
#include "core/scene/scene.hpp"
#include "core/collision/detectors/voxel_exact.hpp"
#include "reference/reference.hpp"
#include "tests/reference/reference_test_worlds.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <map>
#include <random>

using namespace harness;
using namespace harness::reftest;

namespace {

// A closed, non-convex shell: an ellipsoid (3 : 1 : 0.6) bent about the z axis into an arc of
// radius 2.5 (units of r), the ends bent by 69 degrees. The map (X, Y) -> ((Rb - Y) sin(X / Rb),
// Rb - (Rb - Y) cos(X / Rb)) has Jacobian determinant (Rb - Y) / Rb > 0 and is one-to-one for
// these angles: the icosphere's closed, outward 2-manifold stays one, with a concave inner side.
Surface bent_shell(const Vec3& c, double r, int sub) {
  Surface s = icosphere(Vec3::Zero(), 1.0, sub);
  const double Rb = 2.5;
  for (Vec3& v : s.V) {
    const double X = 3.0 * v.x(), Y = v.y(), Z = 0.6 * v.z();
    const double th = X / Rb, rho = Rb - Y;
    v = c + r * Vec3(rho * std::sin(th), Rb - rho * std::cos(th), Z);
  }
  return s;
}

Surface posed(Surface s, const Eigen::Matrix3d& R, const Vec3& t) {
  for (Vec3& v : s.V) v = R * v + t;
  return s;
}

double signed_volume(const Surface& s) {
  double v = 0.0;
  for (const Tri& t : s.F) v += s.V[t[0]].dot(s.V[t[1]].cross(s.V[t[2]]));
  return v / 6.0;
}

double longest_edge(const Surface& s) {
  double l = 0.0;
  for (const Tri& t : s.F)
    for (int k = 0; k < 3; ++k) l = std::max(l, (s.V[t[k]] - s.V[t[(k + 1) % 3]]).norm());
  return l;
}

}  // namespace

TEST_CASE("voxel_exact agrees with CGAL within its band on 1200 random poses", "[voxel_exact][cgal]") {
  std::mt19937 rng(2025);
  std::uniform_real_distribution<double> u(-1.0, 1.0), u01(0.0, 1.0);
  const Surface shapes[] = {icosphere(Vec3::Zero(), 0.02, 2), bent_shell(Vec3::Zero(), 0.01, 3),
                            box_surface(Vec3(-0.03, -0.01, -0.005), Vec3(0.03, 0.01, 0.005), Vec3i(6, 2, 1)),
                            icosphere(Vec3::Zero(), 0.015, 3)};
  for (const Surface& s : shapes) {
    CgalSurface check;
    REQUIRE_NOTHROW(check.set_topology(s.n_surface, s.F));  // closed 2-manifolds
    REQUIRE(signed_volume(s) > 0.0);                         // outward
  }
  const double factors[] = {0.5, 1.0, 1.6, 3.0};  // voxel / L_max before rounding down
  const Region regions[] = {Region::half, Region::full, Region::overlap};
  long long within = 0, beyond = 0, inside_in_band = 0, outside_seen = 0, points = 0, deep_inside = 0, undecided = 0;
  for (int pose = 0; pose < 1200; ++pose) {
    const Surface shape = posed(shapes[pose % 4], random_rotation(rng), 0.01 * Vec3(u(rng), u(rng), u(rng)));
    const double L = longest_edge(shape);
    World w;
    ContactSpec pair = contact_spec_defaults();
    pair.detector = "voxel_exact";
    pair.host = add_body(w, "host", shape);
    pair.voxel_size = factors[(pose / 4) % 4] * L;
    pair.region = regions[(pose / 16) % 3];
    pair.margin = (pose / 48) % 3;
    const double v = round_down_pow2(pair.voxel_size);
    // Guest nodes: near the surface (a random point of a random face moved along its normal by
    // -1.5 v .. +0.5 v), anywhere in the host's box, and a few far outside.
    Points g;
    for (int i = 0; i < 120; ++i) {
      const Tri& t = shape.F[static_cast<std::size_t>(u01(rng) * shape.F.size()) % shape.F.size()];
      double a = u01(rng), b = u01(rng);
      if (a + b > 1.0) a = 1.0 - a, b = 1.0 - b;
      const Vec3 &p0 = shape.V[t[0]], &p1 = shape.V[t[1]], &p2 = shape.V[t[2]];
      const Vec3 n = (p1 - p0).cross(p2 - p0).normalized();
      g.push_back(p0 + a * (p1 - p0) + b * (p2 - p0) + (-1.5 + 2.0 * u01(rng)) * v * n);
    }
    Vec3 lo = shape.V[0], hi = lo;
    for (const Vec3& p : shape.V) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
    for (int i = 0; i < 40; ++i)
      g.push_back(lo + Vec3(u01(rng) * (hi - lo).x(), u01(rng) * (hi - lo).y(), u01(rng) * (hi - lo).z()));
    for (int i = 0; i < 5; ++i) g.push_back(hi + Vec3(u01(rng), u01(rng), u01(rng)) * 0.01);
    pair.guest = harness::test::add_body(w, "guest", harness::test::cloud(g));

    VoxelExactDetector det;
    det.initialize(w, pair);
    std::vector<Contact> contacts;
    det.detect(w, contacts);
    CgalSurface cg;
    const Body& h = w.bodies[pair.host];
    cg.set_topology(h.n_surface, h.faces);
    cg.update(&w.x[h.begin]);
    std::map<int, Contact> found;
    for (const Contact& c : contacts) found[c.guest] = c;
    int counted = 0;
    const Body& gb = w.bodies[pair.guest];
    for (int i = gb.begin; i < gb.end; ++i) {
      const Vec3& x = w.x[i];
      const bool in = cg.strictly_inside(x);
      const double d = std::sqrt(cg.squared_distance(x));
      const double band = det.band_at(x);
      INFO("pose " << pose << " node " << i - gb.begin << " voxel " << v << " L_max " << L << " region "
                   << static_cast<int>(pair.region) << " margin " << pair.margin << " inside " << in << " depth "
                   << d << " band " << band);
      ++points;
      const auto it = found.find(i);
      if (it != found.end()) {
        const VoxelExactDetector::Hit* hit = det.hit(it->second);
        REQUIRE(hit);
        CHECK(hit->band == band);  // the same number both ways
        if (hit->within) {
          REQUIRE(in);
          REQUIRE(std::fabs(hit->depth - d) <= 1e-9);
          ++within;
        } else {
          ++beyond;
          ++counted;
        }
      }
      if (in && d < band) {  // no false negative within the band
        REQUIRE(it != found.end());
        REQUIRE(det.hit(it->second)->within);
        ++inside_in_band;
      }
      if (!in && band > 0.0) ++outside_seen;
      if (in && d >= band) ++deep_inside;
    }
    // Beyond the band: the contacts found beyond it, and the undecided nodes (inside the host's box,
    // nothing listed in their block: no contact, and so not among the nodes found).
    REQUIRE(det.beyond_band() == counted + det.undecided());
    undecided += det.undecided();
  }
  WARN("voxel_exact against CGAL: " << points << " nodes; " << within << " contacts within the band (" << inside_in_band
                                    << " of them checked as CGAL's inside nodes below the band), " << beyond
                                    << " beyond it; " << outside_seen << " outside nodes in the grid; " << deep_inside
                                    << " inside nodes at or beyond the band; " << undecided << " undecided");
  CHECK(within > 20000);
  CHECK(beyond > 1000);
  CHECK(outside_seen > 20000);
}

TEST_CASE("voxel_exact: a node just beyond the band is counted, one just within is not", "[voxel_exact][cgal]") {
  // A box 0.2 x 0.2 x 0.1 m in 0.05 m cells (L_max = 0.0707 m, diagonals), voxel 1/16 m:
  // band = r(x) - 0.0408 m. Along a vertical line below the top face the depth grows by the
  // node's descent and r(x) changes piecewise: bisection finds where depth meets the band.
  World w;
  ContactSpec pair = contact_spec_defaults();
  pair.detector = "voxel_exact";
  pair.host = add_body(w, "host", box_surface(Vec3(-0.1, -0.1, -0.05), Vec3(0.1, 0.1, 0.05), Vec3i(4, 4, 2)));
  pair.guest = harness::test::add_body(w, "guest", harness::test::cloud({Vec3(0.013, -0.021, 0.04)}));
  pair.voxel_size = 1.0 / 16;
  pair.region = Region::full;
  VoxelExactDetector det;
  det.initialize(w, pair);
  std::vector<Contact> contacts;
  const int node = w.bodies[pair.guest].begin;
  auto at = [&](double depth) {
    w.x[node] = Vec3(0.013, -0.021, 0.05 - depth);
    det.detect(w, contacts);
    return det.band_at(w.x[node]) - depth;  // > 0: within the band
  };
  double a = 1e-4, b = 0.045;  // within at a, beyond at b (checked)
  REQUIRE(at(a) > 0.0);
  REQUIRE(at(b) <= 0.0);
  for (int k = 0; k < 200 && b - a > 1e-13; ++k) {
    const double m = 0.5 * (a + b);
    (at(m) > 0.0 ? a : b) = m;
  }
  CgalSurface cg;
  cg.set_topology(w.bodies[pair.host].n_surface, w.bodies[pair.host].faces);
  cg.update(&w.x[w.bodies[pair.host].begin]);
  for (const auto& [depth, inside_band] : {std::pair{a, true}, std::pair{b, false}}) {
    at(depth);
    INFO("depth " << depth << " band " << det.band_at(w.x[node]));
    REQUIRE(contacts.size() == 1);
    const VoxelExactDetector::Hit* hit = det.hit(contacts[0]);
    REQUIRE(hit);
    CHECK(hit->within == inside_band);
    CHECK(det.beyond_band() == (inside_band ? 0 : 1));
    CHECK(hit->depth == Approx(depth).margin(1e-15));
    CHECK(cg.strictly_inside(w.x[node]));
    CHECK(std::fabs(hit->depth - std::sqrt(cg.squared_distance(w.x[node]))) <= 1e-9);
  }
  CHECK(b - a <= 1e-12);
  CHECK(a > 0.001);  // the band is not empty there
}
