// The box detector ("box", the baseline): every guest node inside the host's current bounding box
// and nothing else, in guest order; the nearest host surface vertices by brute force.
#include "core/collision/detectors/box.hpp"
#include "core/collision/detectors/collision_detector.hpp"
#include "core/scene/scene.hpp"
#include "tests/core/collision/collision_test_worlds.hpp"

#include <catch2/catch.hpp>

#include <string>

using namespace harness;
using harness::test::add_body;
using harness::test::cloud;

TEST_CASE("box detector: the guest nodes inside the host's box, boundary included, in guest order") {
  World w;
  // The host: the eight corners of [0, 2] x [0, 1] x [0, 1] as its surface.
  const int host = add_body(w, "host", cloud({Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(0, 1, 0), Vec3(2, 1, 0),
                                             Vec3(0, 0, 1), Vec3(2, 0, 1), Vec3(0, 1, 1), Vec3(2, 1, 1)}, 8));
  const int guest = add_body(w, "guest", cloud({Vec3(1, 0.5, 0.5), Vec3(3, 0.5, 0.5), Vec3(2, 1, 1),
                                               Vec3(-1e-9, 0.5, 0.5), Vec3(1.9, 0.1, 0.9)}, 5));
  ContactSpec spec = contact_spec_defaults();
  spec.host = host, spec.guest = guest, spec.detector = "box";
  BoxDetector d;
  d.initialize(w, spec);
  std::vector<Contact> out;
  d.detect(w, out);
  const int g0 = w.bodies[guest].begin;
  REQUIRE(out.size() == 3);
  CHECK(out[0].guest == g0 + 0);  // the middle
  CHECK(out[1].guest == g0 + 2);  // on the corner: boundary included
  CHECK(out[2].guest == g0 + 4);
  Vec3 lo, hi;
  REQUIRE(d.region(lo, hi));
  CHECK(lo == Vec3(0, 0, 0));
  CHECK(hi == Vec3(2, 1, 1));
  // The host stretches: the box follows it.
  w.x[w.bodies[host].begin + 1] = Vec3(4, 0, 0);
  d.detect(w, out);
  REQUIRE(out.size() == 4);
  CHECK(out[1].guest == g0 + 1);
  // The nearest host surface vertices, nearest first: from (1.9, 0.1, 0.9) the corner (2, 0, 1),
  // then the others in order of distance (checked against every vertex).
  int near[3];
  const int n = d.nearest_hosts(w, Contact{g0 + 4, -1}, 3, near);
  REQUIRE(n == 3);
  CHECK(near[0] == w.bodies[host].begin + 5);
  const Vec3 p = w.x[g0 + 4];
  CHECK((w.x[near[0]] - p).norm() <= (w.x[near[1]] - p).norm());
  CHECK((w.x[near[1]] - p).norm() <= (w.x[near[2]] - p).norm());
  for (int s = 0; s < 8; ++s) {
    const int node = w.bodies[host].begin + s;
    if (node != near[0] && node != near[1] && node != near[2]) CHECK((w.x[node] - p).norm() >= (w.x[near[2]] - p).norm());
  }
  CHECK(std::string(make_detector("box", nullptr)->name()) == "box");
}
