#include "core/scene/scene.hpp"
#include "core/collision/collision.hpp"
#include "core/collision/responses/directions.hpp"
#include "core/collision/responses/force_rule.hpp"
#include "core/collision/responses/force_rules.hpp"
#include "core/collision/responses/line.hpp"
#include "core/collision/responses/plane.hpp"
#include "core/collision/detectors/voxel.hpp"
#include "tests/core/collision/collision_test_worlds.hpp"

#include <catch2/catch.hpp>

#include <map>

#include <algorithm>
#include <cmath>
#include <random>

using namespace harness;
using harness::test::add_body;
using harness::test::cloud;

namespace {

// Reference detector for the eliminator tests: every guest node is a contact, and the nearest
// host nodes are searched over the whole host (no voxels), nearest first, ties by index.
class BruteForceDetector final : public CollisionDetector {
 public:
  const char* name() const override { return "brute"; }
  void initialize(const World&, const ContactSpec& spec) override { host_ = spec.host, guest_ = spec.guest; }
  void detect(const World& w, std::vector<Contact>& out) override {
    out.clear();
    for (int i = w.bodies[guest_].begin; i < w.bodies[guest_].end; ++i) out.push_back({i, -1});
  }
  int nearest_hosts(const World& w, const Contact& c, int k, int* out) const override {
    std::vector<std::pair<double, int>> d;
    for (int i = w.bodies[host_].begin; i < w.bodies[host_].end; ++i)
      d.emplace_back((w.x[i] - w.x[c.guest]).squaredNorm(), i);
    std::sort(d.begin(), d.end());
    const int n = std::min<int>(k, static_cast<int>(d.size()));
    for (int i = 0; i < n; ++i) out[i] = d[i].second;
    return n;
  }

 private:
  int host_ = -1, guest_ = -1;
};

ContactSpec pair_spec(const std::string& e, double voxel = 1.0) {
  ContactSpec s = contact_spec_defaults();
  s.host = 0;
  s.guest = 1;
  s.voxel_size = voxel;
  s.region = Region::full;
  s.eliminator = e;
  set_force_rule(s, "constant", {{"force", 1.0}});  // the paper's constant force, 1 N per contact
  return s;
}

bool finite(const Vec3& v) { return v.allFinite(); }

}  // namespace

TEST_CASE("every elimination has zero net force", "[collision][eliminator]") {
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  int contacts_checked = 0;
  for (int t = 0; t < 300; ++t) {
    Points host(25), guest(25);
    for (auto& p : host) p = Vec3(U(rng), U(rng), U(rng));
    for (auto& p : guest) p = Vec3(U(rng), U(rng), U(rng)) * 0.8 + Vec3(0.3, 0, 0);
    // Coincident and collinear configurations exercise the fallbacks.
    guest[0] = host[0];
    guest[1] = host[1];
    host[2] = host[3] + 0.01 * Vec3(1, 2, 3);
    host[4] = host[3] + 0.02 * Vec3(1, 2, 3);
    World w;
    add_body(w, "host", cloud(host, t % 2 ? 25 : 0));
    add_body(w, "guest", cloud(guest));
    for (const std::string e : {"line", "plane"}) {
      ContactSpec s = pair_spec(e, 0.25 + 0.5 * (t % 3));
      Collision col(w, s);
      col.detect(w);
      const double F = 0.1 + 10.0 * (U(rng) + 1.0);
      auto elim = make_eliminator(e);
      for (const Contact& c : col.contacts()) {
        std::fill(w.f.begin(), w.f.end(), Vec3::Zero());
        elim->eliminate(w, s, col.detector(), {c}, F);
        Vec3 net = Vec3::Zero();
        double applied = 0.0;
        for (const Vec3& f : w.f) {
          REQUIRE(finite(f));
          net += f;
          applied += f.norm();
        }
        CHECK(net.norm() <= 1e-12 * F);
        CHECK(w.f[c.guest].norm() == Approx(F).epsilon(1e-12));
        CHECK(applied == Approx(2.0 * F).epsilon(1e-12));
        ++contacts_checked;
      }
      // And all contacts together, through Collision::step.
      std::fill(w.f.begin(), w.f.end(), Vec3::Zero());
      const PairStep st = col.step(w, 1e-3);
      Vec3 net = Vec3::Zero();
      for (const Vec3& f : w.f) net += f;
      CHECK(net.norm() <= 1e-12 * st.force * std::max(1, st.contacts));
    }
  }
  CHECK(contacts_checked > 1000);
}

TEST_CASE("the line rule pushes the guest away from the nearest host node", "[collision][eliminator]") {
  World w;
  add_body(w, "host", cloud({Vec3(0.1, 0.1, 0.1), Vec3(0.45, 0.45, 0.45), Vec3(-1, -1, -1), Vec3(1, 1, 1)}));
  add_body(w, "guest", cloud({Vec3(0.3, 0.2, 0.1)}));
  ContactSpec s = pair_spec(std::string("line"), 0.5);
  s.force_parameters = {2.0};
  Collision col(w, s);
  const PairStep st = col.step(w, 1e-3);
  REQUIRE(st.contacts == 1);
  CHECK(st.force == 2.0);
  CHECK(st.detect_us >= 0.0);
  CHECK(st.eliminate_us >= 0.0);
  // Nearest host node in the voxel is node 0 (node 1 is farther).
  const Vec3 dir = (w.x[4] - w.x[0]).normalized();
  CHECK((w.f[4] - 2.0 * dir).norm() < 1e-15);
  CHECK((w.f[0] + 2.0 * dir).norm() < 1e-15);
  CHECK(w.f[1].norm() == 0.0);
}

TEST_CASE("plane normal is exact for nodes on known planes", "[collision][eliminator]") {
  Vec3 n;
  // Plane z = 0.3: in-plane differences have zero z, so the cross product is exactly along z.
  REQUIRE(plane_normal(Vec3(0.1, 0.2, 0.3), Vec3(1.7, -0.4, 0.3), Vec3(-0.5, 2.2, 0.3),
                       Vec3(0.2, 0.1, -1.0), Vec3::Zero(), n));
  CHECK(n == Vec3(0, 0, -1));
  REQUIRE(plane_normal(Vec3(0.1, 0.2, 0.3), Vec3(1.7, -0.4, 0.3), Vec3(-0.5, 2.2, 0.3),
                       Vec3(0.2, 0.1, 1.0), Vec3::Zero(), n));
  CHECK(n == Vec3(0, 0, 1));
  // Hint perpendicular to the plane normal: the second hint decides.
  REQUIRE(plane_normal(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(1, 0, 0),
                       Vec3(0, 0, -2), n));
  CHECK(n == Vec3(0, 0, -1));

  // Random planes, random points on them.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  for (int t = 0; t < 500; ++t) {
    const Vec3 normal = Vec3(U(rng), U(rng), U(rng)).normalized();
    const Vec3 u = normal.unitOrthogonal(), v = normal.cross(u);
    const Vec3 o = Vec3(U(rng), U(rng), U(rng)) * 10.0;
    const double scale = std::exp2(8.0 * U(rng));
    auto on = [&]() { return o + scale * (U(rng) * u + U(rng) * v); };
    const Vec3 p0 = on(), p1 = on(), p2 = on();
    if ((p1 - p0).cross(p2 - p0).norm() < 1e-3 * scale * scale) continue;
    const Vec3 hint = normal * (t % 2 ? 1.0 : -1.0) + 0.3 * Vec3(U(rng), U(rng), U(rng));
    REQUIRE(plane_normal(p0, p1, p2, hint, Vec3::Zero(), n));
    CHECK(std::fabs(n.norm() - 1.0) < 1e-14);
    CHECK((n - normal * (t % 2 ? 1.0 : -1.0)).norm() < 1e-9);
  }

  // Through the whole pipeline: three host nodes on the plane z = 1 and a deep node far below;
  // the guest just under the plane is pushed along +z (the hints point up from the centre).
  World w;
  add_body(w, "host", cloud({Vec3(0.3, 0, 1), Vec3(-0.2, 0.25, 1), Vec3(-0.1, -0.3, 1), Vec3(0, 0, -5)}));
  add_body(w, "guest", cloud({Vec3(0, 0, 0.9)}));
  ContactSpec s = pair_spec(std::string("plane"), 2.0);
  s.force_parameters = {3.0};
  Collision col(w, s);
  REQUIRE(col.step(w, 1e-3).contacts == 1);
  CHECK(w.f[4] == Vec3(0, 0, 3.0));
  for (int i = 0; i < 3; ++i) CHECK(w.f[i] == Vec3(0, 0, -1.0));
  CHECK(w.f[3] == Vec3::Zero());
}

TEST_CASE("plane rule pushes a guest inside a flat layer outward", "[collision][eliminator]") {
  // 5 x 5 x 2 cells of 1 m: top z = 2, bottom z = 0, sides x, y = 0 and 5.
  const auto layer = harness::test::box_lattice(Vec3(0, 0, 0), Vec3(5, 5, 2), Vec3i(5, 5, 2));
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> off(0.2, 0.4), depth(0.02, 0.14), flip(0.0, 1.0);
  std::uniform_int_distribution<int> cell(0, 4), zc(0, 1);
  int pushed = 0;
  for (int t = 0; t < 300; ++t) {
    // Offsets in [0.2, 0.4] from a lattice node and close to one face keep the three nearest
    // host nodes on that face.
    const int face = t % 6;  // -x, +x, -y, +y, -z, +z
    const int axis = face / 2;
    const bool plus = face % 2;
    Vec3 p;
    Vec3 outward = Vec3::Zero();
    outward[axis] = plus ? 1.0 : -1.0;
    const double top = axis == 2 ? 2.0 : 5.0;
    for (int a = 0; a < 3; ++a) {
      if (a == axis) {
        p[a] = plus ? top - depth(rng) : depth(rng);
      } else {
        const double base = a == 2 ? zc(rng) : cell(rng);
        p[a] = base + (flip(rng) < 0.5 ? off(rng) : 1.0 - off(rng));
      }
    }
    World w;
    add_body(w, "layer", layer);
    add_body(w, "tool", cloud({p}));
    for (bool voxels : {false, true}) {
      std::fill(w.f.begin(), w.f.end(), Vec3::Zero());
      ContactSpec s = pair_spec(std::string("plane"), 1.0);
      std::vector<Contact> contacts;
      PlaneEliminator elim;
      if (voxels) {
        VoxelDetector det;
        det.initialize(w, s);
        det.detect(w, contacts);
        if (contacts.empty()) continue;
        elim.eliminate(w, s, det, contacts, 1.0);
      } else {
        BruteForceDetector det;
        det.initialize(w, s);
        det.detect(w, contacts);
        elim.eliminate(w, s, det, contacts, 1.0);
      }
      const Vec3 f = w.f[w.bodies[1].begin];
      INFO("guest " << p.transpose() << " voxels " << voxels);
      CHECK((f - outward).norm() < 1e-12);
      ++pushed;
    }
  }
  CHECK(pushed > 400);
}

TEST_CASE("plane rule pushes a guest inside a sphere outward", "[collision][eliminator]") {
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> U(-1.0, 1.0), R(0.1, 0.78);
  for (int t = 0; t < 200; ++t) {
    const Vec3 centre(U(rng), U(rng), U(rng));
    // A random rotation, so that no symmetry of the axes helps.
    const Eigen::Quaterniond q = Eigen::Quaterniond(U(rng), U(rng), U(rng), U(rng)).normalized();
    auto ico = harness::test::icosahedron(Vec3::Zero(), 1.0, false);
    for (auto& p : ico.nodes) p = centre + q * p;
    World w;
    add_body(w, "implant", ico);
    // The guest on the axis of a face, inside (the inradius is 0.795): the face's vertices are
    // its three nearest host nodes.
    const Tri& face = ico.faces[t % ico.faces.size()];
    const Vec3 a = ico.nodes[face[0]], b = ico.nodes[face[1]], c = ico.nodes[face[2]];
    const Vec3 fn = (b - a).cross(c - a).normalized();
    const Vec3 g = centre + R(rng) * ((a + b + c) / 3.0 - centre).normalized();
    add_body(w, "tissue", cloud({g}));
    ContactSpec s = pair_spec(std::string("plane"));
    BruteForceDetector det;
    det.initialize(w, s);
    std::vector<Contact> contacts;
    det.detect(w, contacts);
    PlaneEliminator elim;
    elim.eliminate(w, s, det, contacts, 1.0);
    const Vec3 f = w.f[w.bodies[1].begin];
    CHECK(f.dot(g - centre) > 0.0);
    CHECK((f - fn).norm() < 1e-12);
  }
}

// orient (ContactSpec): a guest inside an icosahedron on the axis of a face, nearer the centre than
// the face (so the line to the nearest vertex points inward). `outward` pushes it out with either
// rule, `guest` pushes it along the way it came in (toward it from the host node or the plane),
// `paper` is line inward, plane outward: the confound of claim (a). Forces sum to zero each time.
TEST_CASE("orient decides which way line and plane push a node that crossed the surface", "[collision][eliminator]") {
  std::mt19937 rng(23);
  std::uniform_real_distribution<double> U(-1.0, 1.0), R(0.1, 0.7);
  const std::map<std::pair<Orient, std::string>, int> expect = {
      {{Orient::paper, std::string("line")}, -1},   {{Orient::paper, std::string("plane")}, +1},
      {{Orient::guest, std::string("line")}, -1},   {{Orient::guest, std::string("plane")}, -1},
      {{Orient::outward, std::string("line")}, +1}, {{Orient::outward, std::string("plane")}, +1}};
  int checked = 0;
  for (int t = 0; t < 100; ++t) {
    const Vec3 centre(U(rng), U(rng), U(rng));
    const Eigen::Quaterniond q = Eigen::Quaterniond(U(rng), U(rng), U(rng), U(rng)).normalized();
    auto ico = harness::test::icosahedron(Vec3::Zero(), 1.0, false);
    for (auto& p : ico.nodes) p = centre + q * p;
    const Tri& face = ico.faces[t % ico.faces.size()];
    const Vec3 g = centre + R(rng) * ((ico.nodes[face[0]] + ico.nodes[face[1]] + ico.nodes[face[2]]) / 3.0 - centre).normalized();
    for (const auto& [key, sign] : expect) {
      World w;
      add_body(w, "implant", ico);
      add_body(w, "tissue", cloud({g}));
      ContactSpec s = pair_spec(key.second);
      s.orient = key.first;
      BruteForceDetector det;
      det.initialize(w, s);
      std::vector<Contact> contacts;
      det.detect(w, contacts);
      if (key.second == std::string("line")) LineEliminator().eliminate(w, s, det, contacts, 1.0);
      else PlaneEliminator().eliminate(w, s, det, contacts, 1.0);
      const Vec3 f = w.f[w.bodies[1].begin];
      Vec3 total = Vec3::Zero();
      for (const Vec3& fi : w.f) total += fi;
      INFO("orient " << static_cast<int>(key.first) << " eliminator " << key.second);
      CHECK(sign * f.dot(g - centre) > 0.0);
      CHECK(total.norm() < 1e-12);
      ++checked;
    }
  }
  CHECK(checked == 600);
}

TEST_CASE("degenerate contacts give finite forces", "[collision][eliminator]") {
  // Coincident guest and host surface vertex: the outward vertex normal.
  const auto box = harness::test::box_lattice(Vec3(0, 0, 0), Vec3(2, 2, 2), Vec3i(2, 2, 2));
  {
    World w;
    add_body(w, "host", box);
    add_body(w, "guest", cloud({box.nodes[0]}));  // node 0 is the corner (0, 0, 0)
    const Vec3 c(1, 1, 1);
    CHECK((host_outward_hint(w, 0, 0, c) - Vec3(-1, -1, -1).normalized()).norm() < 1e-15);
    CHECK((line_direction(w, 0, w.bodies[1].begin, 0, c) - Vec3(-1, -1, -1).normalized()).norm() < 1e-15);
    // The interior node (1, 1, 1) is the last one and sits at the centre: zero hint.
    const int centre_node = w.bodies[0].end - 1;
    REQUIRE(w.x[centre_node] == c);
    CHECK(host_outward_hint(w, 0, centre_node, c) == Vec3::Zero());
    // A guest there too: hint zero, centre->guest zero -> +z.
    w.x[w.bodies[1].begin] = c;
    CHECK(line_direction(w, 0, w.bodies[1].begin, centre_node, c) == Vec3::UnitZ());
    for (const std::string e : {"line", "plane"}) {
      std::fill(w.f.begin(), w.f.end(), Vec3::Zero());
      ContactSpec s = pair_spec(e, 0.5);
      s.force_parameters = {1.5};
      Collision col(w, s);
      REQUIRE(col.step(w, 1e-3).contacts == 1);
      for (const Vec3& f : w.f) CHECK(finite(f));
      if (e == std::string("line")) CHECK(w.f[w.bodies[1].begin] == Vec3(0, 0, 1.5));
      CHECK(w.f[w.bodies[1].begin].norm() == Approx(1.5));
    }
  }
  // Interior hint: the direction from the host's centre to the node.
  {
    World w;
    add_body(w, "host", cloud({Vec3(0, 0, 0), Vec3(4, 2, 2), Vec3(3, 1, 1)}));
    add_body(w, "guest", cloud({Vec3(3, 1, 1)}));
    CHECK((line_direction(w, 0, 3, 2, Vec3(2, 1, 1)) - Vec3(1, 0, 0)).norm() < 1e-15);
  }
  // Collinear, near-collinear and coincident neighbours: the line rule with the nearest node.
  Vec3 n;
  CHECK_FALSE(plane_normal(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0), Vec3::UnitZ(), Vec3::Zero(), n));
  CHECK_FALSE(plane_normal(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 1e-13, 0), Vec3::UnitZ(), Vec3::Zero(), n));
  CHECK(plane_normal(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 1e-11, 0), Vec3::UnitZ(), Vec3::Zero(), n));
  CHECK_FALSE(plane_normal(Vec3(1, 1, 1), Vec3(1, 1, 1), Vec3(1, 1, 1), Vec3::UnitZ(), Vec3::Zero(), n));
  const double nan = std::nan("");
  CHECK_FALSE(plane_normal(Vec3(nan, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3::UnitZ(), Vec3::Zero(), n));
  for (const Points& host : {Points{Vec3(0, 0, 0), Vec3(0.1, 0, 0), Vec3(0.2, 0, 0)},
                             Points{Vec3(0, 0, 0), Vec3(0.1, 0, 0)},
                             Points{Vec3(0, 0, 0), Vec3(0, 0, 0), Vec3(0, 0, 0)}}) {
    World w;
    add_body(w, "host", cloud(host));
    add_body(w, "guest", cloud({Vec3(0.03, 0.05, 0.0)}));  // node 0 strictly nearest
    const int g = w.bodies[1].begin;
    ContactSpec s = pair_spec(std::string("plane"), 1.0);
    Collision col(w, s);
    REQUIRE(col.step(w, 1e-3).contacts == 1);
    int h = -1;
    col.detector().nearest_hosts(w, col.contacts()[0], 1, &h);
    const Vec3 expect = (w.x[g] - w.x[h]).normalized();
    CHECK((w.f[g] - expect).norm() < 1e-15);
    CHECK((w.f[h] + expect).norm() < 1e-15);
  }
  // Huge but finite coordinates: unit directions without overflow.
  {
    World w;
    add_body(w, "host", cloud({Vec3(-1e300, 0, 0), Vec3(1e300, 1e300, 0)}));
    add_body(w, "guest", cloud({Vec3(-1e300, 0, 0)}));
    const Vec3 d = line_direction(w, 0, 2, 1, Vec3(0, 5e299, 0));
    CHECK(finite(d));
    CHECK(d.norm() == Approx(1.0));
  }
}

TEST_CASE("automatic force makes each contact separate at v_sep within the step", "[collision][eliminator]") {
  std::mt19937 rng(23);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  const double dt = 1e-3, vsep = 0.01;
  auto vel = [](const World& x, int i) { return !x.is_free(i) ? x.kin_v[i] : x.v[i]; };
  auto acc = [](const World& x, int i) { return !x.is_free(i) ? Vec3(Vec3::Zero()) : Vec3(x.f[i] / x.m[i]); };
  auto inv = [](const World& x, int i) { return !x.is_free(i) ? 0.0 : 1.0 / x.m[i]; };
  for (int t = 0; t < 100; ++t) {
    Points host(30), guest(30);
    for (auto& p : host) p = Vec3(U(rng), U(rng), U(rng));
    for (auto& p : guest) p = Vec3(U(rng), U(rng), U(rng));
    World w;
    add_body(w, "host", cloud(host));
    add_body(w, "guest", cloud(guest));
    for (int i = 0; i < w.num_nodes(); ++i) {
      w.f[i] = Vec3(U(rng), U(rng), U(rng)) * 50.0;
      w.v[i] = Vec3(U(rng), U(rng), U(rng)) * 0.1;
      w.m[i] = 0.01 * (2.0 + U(rng));
      w.inv_m[i] = 1.0 / w.m[i];
    }
    w.kinematic[3] = Kinematic::pinned;
    w.kin_v[3] = Vec3(0, 0, -1);
    for (const std::string e : {"line", "plane"}) {
      World x = w;
      ContactSpec s = pair_spec(e, 0.5);
      set_force_rule(s, "auto");
      Collision col(x, s);
      col.detect(x);
      REQUIRE(!col.contacts().empty());
      std::vector<Push> pushes;
      col.eliminator().pushes(x, s, col.detector(), col.contacts(), pushes);
      REQUIRE(pushes.size() == col.contacts().size());
      // Independent evaluation of the documented formula.
      std::map<int, int> share;
      for (const Push& p : pushes)
        for (int k = 0; k < p.count; ++k) ++share[p.hosts[k]];
      std::vector<double> want;
      for (const Push& p : pushes) {
        Vec3 dv = vel(x, p.guest), da = acc(x, p.guest);
        double c = inv(x, p.guest);
        for (int k = 0; k < p.count; ++k) {
          dv -= p.weight[k] * vel(x, p.hosts[k]);
          da -= p.weight[k] * acc(x, p.hosts[k]);
          c += p.weight[k] * p.weight[k] * share[p.hosts[k]] * inv(x, p.hosts[k]);
        }
        want.push_back(c > 0.0 ? std::max(0.0, vsep - dv.dot(p.n) - dt * da.dot(p.n)) / (dt * c) : 0.0);
      }
      std::vector<double> got;
      std::vector<int> scratch;
      const double largest = auto_contact_forces(x, pushes, dt, vsep, got, scratch);
      for (int v : scratch) CHECK(v == 0);
      REQUIRE(got.size() == want.size());
      for (std::size_t i = 0; i < got.size(); ++i) CHECK(got[i] == Approx(want[i]).epsilon(1e-12).margin(1e-12));
      CHECK(largest == *std::max_element(got.begin(), got.end()));
      // For a contact alone on its hosts, the push leaves it separating at exactly v_sep
      // (or faster, when it already was).
      for (std::size_t i = 0; i < pushes.size(); ++i) {
        const Push& p = pushes[i];
        bool alone = p.count > 0;
        for (int k = 0; k < p.count; ++k) alone = alone && share[p.hosts[k]] == 1;
        if (!alone) continue;
        Vec3 vg = vel(x, p.guest) + dt * (acc(x, p.guest) + got[i] * inv(x, p.guest) * p.n);
        Vec3 vh = Vec3::Zero();
        for (int k = 0; k < p.count; ++k)
          vh += p.weight[k] * (vel(x, p.hosts[k]) + dt * (acc(x, p.hosts[k]) - p.weight[k] * got[i] * inv(x, p.hosts[k]) * p.n));
        if (inv(x, p.guest) == 0.0 && std::all_of(p.hosts, p.hosts + p.count, [&](int h) { return inv(x, h) == 0.0; })) continue;
        CHECK((vg - vh).dot(p.n) >= vsep - 1e-9);
      }
    }
  }
  // A resting overlap with no load is pushed apart at the separation speed; no contacts: 0.
  World w;
  add_body(w, "host", cloud({Vec3(0, 0, 0), Vec3(1, 1, 1)}));
  add_body(w, "guest", cloud({Vec3(0.1, 0.1, 0.1), Vec3(9, 9, 9)}));
  ContactSpec s = pair_spec(std::string("line"), 0.5);
  set_force_rule(s, "auto");
  Collision col(w, s);
  PairStep st = col.step(w, dt);
  CHECK(st.contacts == 1);
  const double mu = w.m[0] * w.m[2] / (w.m[0] + w.m[2]);
  CHECK(st.force == Approx(mu * col.voxel_size() / s.separation_time / dt));
  w.x[2] = Vec3(5, 5, 5);
  st = col.step(w, dt);
  CHECK(st.contacts == 0);
  CHECK(st.force == 0.0);
}

TEST_CASE("contact damping takes energy out of a contact and never pulls", "[collision][eliminator][damping]") {
  // One guest node inside the host's voxel, pushed by the paper's constant 1 N along the line from
  // the nearest host node (at rest); with damping c the force is max(0, 1 - c v_n), v_n its speed
  // away from the host along the push: its power on the pair's relative motion falls by c v_n^2.
  const double dt = 1e-4, c = 2.0;
  auto run = [&](double damping, double vn) {
    World w;
    add_body(w, "host", cloud({Vec3(0, 0, 0), Vec3(1, 1, 1)}));
    add_body(w, "guest", cloud({Vec3(0.1, 0.1, 0.1), Vec3(9, 9, 9)}));
    ContactSpec s = pair_spec(std::string("line"), 0.5);
    s.damping = damping;
    const Vec3 n = Vec3(1, 1, 1).normalized();
    w.v[2] = vn * n;
    for (Vec3& f : w.f) f.setZero();
    Collision col(w, s);
    const PairStep st = col.step(w, dt);
    REQUIRE(st.contacts == 1);
    CHECK((w.f[2] - st.force * n).norm() < 1e-12);
    CHECK((w.f[0] + w.f[2]).norm() < 1e-12);  // the host node takes the reaction
    return st.force;
  };
  CHECK(run(0.0, -0.3) == Approx(1.0));        // no damping: the paper's force
  CHECK(run(c, 0.0) == Approx(1.0));           // at rest: unchanged
  CHECK(run(c, -0.3) == Approx(1.0 + c * 0.3));  // approaching: more
  CHECK(run(c, 0.2) == Approx(1.0 - c * 0.2));   // separating: less
  CHECK(run(c, 2.0) == 0.0);                   // separating faster than F / c: none, never a pull
}
