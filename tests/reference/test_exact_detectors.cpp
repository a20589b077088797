// The exact detectors ("cgal", "fcl") behind the core CollisionDetector interface.
#include "core/parallel.hpp"
#include "core/scene/scene.hpp"
#include "core/simulation.hpp"
#include "core/state_hash.hpp"
#include "reference/reference.hpp"
#include "tests/reference/reference_test_worlds.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

using namespace harness;
using namespace harness::reftest;

namespace {
struct TwoSpheres {
  World w;
  ContactSpec pair = contact_spec_defaults();
  TwoSpheres() {
    Surface guest = icosphere(Vec3(1.5, 0.1, 0.05), 1.0, 2);
    guest.V.push_back(Vec3(0.7, 0.1, 0.05));  // an interior node, inside the host too
    guest.V.push_back(Vec3(2.0, 0.1, 0.05));  // an interior node outside the host
    pair.host = add_body(w, "host", icosphere(Vec3::Zero(), 1.0, 3));
    pair.guest = add_body(w, "guest", guest);
  }
};
}  // namespace

TEST_CASE("exact detectors are made by kind through the reference library's maker", "[reference][detector]") {
  CHECK(std::string(make_detector("cgal", make_exact_detector)->name()) == "cgal");
  CHECK(std::string(make_detector("fcl", make_exact_detector)->name()) == "fcl");
  CHECK(std::string(make_detector("voxel", make_exact_detector)->name()) == "voxel");
  CHECK_THROWS_AS(make_exact_detector("voxel"), std::invalid_argument);
}

TEST_CASE("cgal detector: contacts are the truly penetrating guest nodes", "[reference][detector][cgal]") {
  TwoSpheres s;
  CgalDetector det;
  det.initialize(s.w, s.pair);
  std::vector<Contact> contacts;
  det.detect(s.w, contacts);
  ReferenceSpec spec = reference_spec_defaults();
  spec.cgal = true;
  ReferenceMeasurer m(s.w, s.pair, spec);
  Measurement out;
  m.measure(s.w, s.pair, contacts, out);
  REQUIRE(out.true_pen_guest > 0);
  CHECK(static_cast<int>(contacts.size()) == out.true_pen_guest);
  CHECK(out.tp == out.true_pen_guest);
  CHECK(out.fp == 0);
  CHECK(out.fn == 0);
  const Body& G = s.w.bodies[s.pair.guest];
  const Body& H = s.w.bodies[s.pair.host];
  CHECK(std::any_of(contacts.begin(), contacts.end(), [&](const Contact& c) { return c.guest == G.end - 2; }));
  CHECK(std::none_of(contacts.begin(), contacts.end(), [&](const Contact& c) { return c.guest == G.end - 1; }));

  for (const Contact& c : contacts) {
    int hosts[5] = {-1, -1, -1, -1, -1};
    REQUIRE(det.nearest_hosts(s.w, c, 5, hosts) == 3);  // k > 3 gives the triangle's 3
    CHECK(hosts[3] == -1);
    const Vec3& p = s.w.x[c.guest];
    for (int j = 0; j < 3; ++j) {
      CHECK(hosts[j] >= H.begin);
      CHECK(hosts[j] < H.begin + H.n_surface);
    }
    CHECK((s.w.x[hosts[0]] - p).norm() <= (s.w.x[hosts[1]] - p).norm());
    CHECK((s.w.x[hosts[1]] - p).norm() <= (s.w.x[hosts[2]] - p).norm());
    // The triangle holds the nearest surface point: its nearest vertex is no farther than the
    // distance to the surface plus the triangle's size.
    const double d = std::sqrt(m.cgal_surface(true).squared_distance(p));
    CHECK((s.w.x[hosts[0]] - p).norm() <= d + 0.2);
    int one = -1;
    CHECK(det.nearest_hosts(s.w, c, 1, &one) == 1);
    CHECK(one == hosts[0]);
  }

  // Moved apart: no contacts (the tree follows the host).
  translate_body(s.w, s.pair.host, Vec3(-5, 0, 0));
  det.detect(s.w, contacts);
  CHECK(contacts.empty());
}

TEST_CASE("fcl detector: guest vertices of intersecting triangles", "[reference][detector][fcl]") {
  TwoSpheres s;
  FclDetector det;
  det.initialize(s.w, s.pair);
  std::vector<Contact> contacts;
  det.detect(s.w, contacts);
  REQUIRE(!contacts.empty());
  const Body& G = s.w.bodies[s.pair.guest];
  const Body& H = s.w.bodies[s.pair.host];

  // Oracle: vertices of guest triangles in the all-pairs intersecting list.
  FclSurface fg, fh;
  fg.set_topology(G.n_surface, G.faces);
  fg.update(&s.w.x[G.begin]);
  fh.set_topology(H.n_surface, H.faces);
  fh.update(&s.w.x[H.begin]);
  std::vector<TrianglePair> brute;
  intersecting_pairs_brute_force(fg, fh, brute);
  std::set<int> expected;
  std::set<std::pair<int, int>> tri_pairs;
  for (const TrianglePair& p : brute) {
    tri_pairs.insert({p.a, p.b});
    for (int v : G.faces[p.a]) expected.insert(G.begin + v);
  }
  std::set<int> got;
  for (const Contact& c : contacts) got.insert(c.guest);
  CHECK(got == expected);
  CHECK(got.size() == contacts.size());  // each node once
  CHECK(std::is_sorted(contacts.begin(), contacts.end(),
                       [](const Contact& a, const Contact& b) { return a.guest < b.guest; }));

  for (const Contact& c : contacts) {
    // The key is a host triangle intersecting one of the node's triangles.
    const int v = c.guest - G.begin;
    bool ok = false;
    for (int f = 0; f < static_cast<int>(G.faces.size()); ++f)
      if (std::find(G.faces[f].begin(), G.faces[f].end(), v) != G.faces[f].end() && tri_pairs.count({f, c.key}))
        ok = true;
    CHECK(ok);
    int hosts[3];
    REQUIRE(det.nearest_hosts(s.w, c, 3, hosts) == 3);
    const Vec3& p = s.w.x[c.guest];
    CHECK((s.w.x[hosts[0]] - p).norm() <= (s.w.x[hosts[1]] - p).norm());
    CHECK((s.w.x[hosts[1]] - p).norm() <= (s.w.x[hosts[2]] - p).norm());
    for (int h : hosts) CHECK((h >= H.begin && h < H.begin + H.n_surface));
  }

  // Twice in a row: the same answer (the per-node scratch is reset).
  std::vector<Contact> again;
  det.detect(s.w, again);
  CHECK(again.size() == contacts.size());

  translate_body(s.w, s.pair.guest, Vec3(5, 0, 0));
  det.detect(s.w, contacts);
  CHECK(contacts.empty());
}

TEST_CASE("a diverged state: no contacts, no measurement, no abort", "[reference][detector]") {
  TwoSpheres s;
  CgalDetector cg;
  FclDetector fc;
  cg.initialize(s.w, s.pair);
  fc.initialize(s.w, s.pair);
  ReferenceSpec spec = reference_spec_defaults();
  spec.cgal = spec.fcl = spec.ccd = true;
  ReferenceMeasurer m(s.w, s.pair, spec);
  s.w.x[s.w.bodies[s.pair.guest].begin + 3].x() = std::numeric_limits<double>::quiet_NaN();
  std::vector<Contact> contacts = {{0, 0}};
  cg.detect(s.w, contacts);
  CHECK(contacts.empty());
  contacts = {{0, 0}};
  fc.detect(s.w, contacts);
  CHECK(contacts.empty());
  Measurement out;
  out.has_cgal = true;
  m.measure(s.w, s.pair, {}, out);
  CHECK_FALSE(out.has_cgal);
  CHECK_FALSE(out.has_fcl);
  CHECK_FALSE(out.has_ccd);
}

TEST_CASE("CGAL detection overlapping the springs' pass: the same state and contacts as one thread",
          "[reference][detector][cgal][parallel]") {
  // Each bundled scene with its own contact (CGAL both ways), 60 steps from rest and 60 steps of
  // its contact phase: one thread, then two and three with the detection always overlapped.
  const int threads_before = threads();
  for (const char* name : {"sphere_collision", "cylinder_press", "implant_expansion"}) {
    Scene scene = load_scene(std::string(HARNESS_SOURCE_DIR) + "/experiments/scenes/" + name + ".json",
                             {{"references.solvers", "[]"}, {"output.frames_every", "0"}});
    auto run = [&](int t, SimulationOptions::Overlap overlap, std::vector<int>& contacts) {
      set_threads(t);
      SimulationOptions so;
      so.exact_detectors = make_exact_detector;
      so.overlap = overlap;
      Simulation sim(scene, so);
      for (int s = 0; s < 1500; ++s) {
        sim.step();
        if (s >= 1440) contacts.push_back(sim.pairs().at(0).last.contacts);
      }
      return state_hash(sim.world());
    };
    std::vector<int> c1, c2, c3;
    const std::string h1 = run(1, SimulationOptions::Overlap::never, c1);
    INFO(name);
    CHECK(run(2, SimulationOptions::Overlap::always, c2) == h1);
    CHECK(run(3, SimulationOptions::Overlap::always, c3) == h1);
    CHECK(c2 == c1);
    CHECK(c3 == c1);
  }
  set_threads(threads_before);
}
