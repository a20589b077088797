// The paper's grid with an exact narrow phase (core/collision/detectors/voxel_exact.hpp) without
// the reference library: depths and normals computed by hand, the responses along its normal
// conserving momentum both ways, the energy audit of an undamped drop, the same answer for any
// thread count, no growth per step, and what it refuses. Its agreement with CGAL on random poses
// is in tests/reference/test_voxel_exact.cpp.
#include "core/collision/responses/force_rule.hpp"
#include "core/collision/collision.hpp"
#include "core/collision/detectors/voxel_exact.hpp"
#include "core/collision/responses/force_rules.hpp"
#include "core/parallel.hpp"
#include "core/scene/scene.hpp"
#include "core/simulation.hpp"
#include "tests/core/collision/collision_test_worlds.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>

using namespace harness;
using harness::test::add_body;
using harness::test::box_lattice;
using harness::test::cloud;
using harness::test::icosahedron;

namespace {

struct ThreadsGuard {
  int t = threads();
  std::size_t g = parallel_grain();
  ~ThreadsGuard() {
    set_threads(t);
    set_parallel_grain(g);
  }
};

ContactSpec exact_spec(double voxel, Region region = Region::full) {
  ContactSpec s = contact_spec_defaults();
  s.host = 0;
  s.guest = 1;
  s.detector = "voxel_exact";
  s.voxel_size = voxel;
  s.region = region;
  return s;
}

const VoxelExactDetector& exact(const Collision& c) { return dynamic_cast<const VoxelExactDetector&>(c.detector()); }

}  // namespace

TEST_CASE("voxel_exact: a node under a flat box face, depth and normal by hand", "[collision][voxel_exact]") {
  // A 4 x 4 x 2 lattice of 0.25 m cells: surface edges 0.25 m and diagonals 0.354 m; voxel 0.5 m:
  // band >= 0.5 - 0.354 / sqrt(3) = 0.296 m everywhere inside the region.
  World w;
  add_body(w, "box", box_lattice(Vec3(0, 0, 0), Vec3(1, 1, 0.5), Vec3i(4, 4, 2)));
  const double depth = 0.0731;
  const Vec3 x(0.4137, 0.6021, 0.5 - depth);  // nearest to the top face (sides 0.41 away)
  // Below the face; above it (outside); the slab's centre, 0.25 m from the top and the bottom:
  // inside, its block (cells -1..1 around the grid's centre) reaching both faces' vertices.
  add_body(w, "guest", cloud({x, Vec3(0.4, 0.6, 0.5 + 0.01), Vec3(0.5, 0.5, 0.25)}));
  Collision col(w, exact_spec(0.5));
  REQUIRE(col.detect(w) == 2);
  const Contact c = col.contacts()[0];
  CHECK(c.guest == w.bodies[1].begin);
  const auto& det = exact(col);
  const VoxelExactDetector::Hit* h = det.hit(c);
  REQUIRE(h);
  CHECK(h->depth == Approx(depth).epsilon(1e-13));
  CHECK(h->within);
  CHECK(h->feature == VoxelExactDetector::kInterior);
  ContactPoint cp;
  REQUIRE(col.detector().contact_point(w, c, cp));
  CHECK((cp.normal - Vec3(0, 0, 1)).norm() < 1e-13);
  CHECK(cp.depth == Approx(depth).epsilon(1e-13));
  const Vec3 p = cp.weight[0] * w.x[cp.hosts[0]] + cp.weight[1] * w.x[cp.hosts[1]] + cp.weight[2] * w.x[cp.hosts[2]];
  CHECK((p - Vec3(x.x(), x.y(), 0.5)).norm() < 1e-13);
  CHECK(cp.weight[0] + cp.weight[1] + cp.weight[2] == Approx(1.0).epsilon(1e-15));
  Vec3 n;
  REQUIRE(col.detector().contact_direction(w, c, n));
  CHECK((n - Vec3(0, 0, 1)).norm() < 1e-13);
  int hosts[3];
  REQUIRE(col.detector().nearest_hosts(w, c, 3, hosts) == 3);
  for (int k = 0; k < 3; ++k) CHECK(w.x[hosts[k]].z() == 0.5);
  CHECK((w.x[hosts[0]] - x).norm() <= (w.x[hosts[1]] - x).norm());
  CHECK((w.x[hosts[1]] - x).norm() <= (w.x[hosts[2]] - x).norm());
  const Contact centre = col.contacts()[1];
  CHECK(centre.guest == w.bodies[1].begin + 2);
  REQUIRE(det.hit(centre));
  CHECK(det.hit(centre)->depth == Approx(0.25).epsilon(1e-13));
  CHECK(det.hit(centre)->within);  // r = 0.5 (one voxel to its block's faces), band 0.296
  CHECK(det.beyond_band() == 0);
}

TEST_CASE("voxel_exact: a node inside an icosahedron, depth to the face plane by hand", "[collision][voxel_exact]") {
  // Inradius of the unit icosahedron: the distance from its centre to a face plane.
  const double edge = 4.0 / std::sqrt(10.0 + 2.0 * std::sqrt(5.0));
  const double inradius = std::sqrt(3.0) / 12.0 * (3.0 + std::sqrt(5.0)) * edge;  // 0.7947
  World w;
  add_body(w, "ico", icosahedron(Vec3(0.3, -0.2, 0.1), 1.0, false));
  const Body& b = w.bodies[0];
  const Tri& t = b.faces[7];
  const Vec3 a = w.x[b.begin + t[0]], bb = w.x[b.begin + t[1]], c = w.x[b.begin + t[2]];
  const Vec3 nf = (bb - a).cross(c - a).normalized();
  const Vec3 centroid = (a + bb + c) / 3.0;
  REQUIRE((centroid - Vec3(0.3, -0.2, 0.1)).norm() == Approx(inradius).epsilon(1e-12));
  const double s = 0.55;  // from the centre along the face's normal: depth inradius - s
  add_body(w, "guest", cloud({Vec3(0.3, -0.2, 0.1) + s * nf}));
  Collision col(w, exact_spec(2.0));
  REQUIRE(col.detect(w) == 1);
  const Contact k = col.contacts()[0];
  CHECK(k.key == 7);
  ContactPoint cp;
  REQUIRE(col.detector().contact_point(w, k, cp));
  CHECK(cp.depth == Approx(inradius - s).epsilon(1e-12));
  CHECK((cp.normal - nf).norm() < 1e-12);
  for (int j = 0; j < 3; ++j) CHECK(cp.weight[j] == Approx(1.0 / 3.0).epsilon(1e-12));
  CHECK(exact(col).hit(k)->within);
  // Just outside the face plane: outside, no contact.
  w.x[w.bodies[1].begin] = Vec3(0.3, -0.2, 0.1) + (inradius + 1e-9) * nf;
  CHECK(col.detect(w) == 0);
}

TEST_CASE("voxel_exact: every response along its normal conserves momentum, both ways", "[collision][voxel_exact]") {
  std::mt19937 rng(77);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int pushing = 0;
  struct Rule {
    std::string e;
    const char* r;
  };
  for (int t = 0; t < 30; ++t)
    for (const Rule& rule : {Rule{std::string("line"), "constant"}, Rule{std::string("line"), "auto"},
                             Rule{std::string("line"), "penalty"}, Rule{std::string("plane"), "penalty"}})
      for (bool two_sided : {false, true}) {
        World w;
        add_body(w, "host", box_lattice(Vec3(0, 0, 0), Vec3(1, 1, 0.5), Vec3i(5, 5, 3)));
        add_body(w, "guest", icosahedron(Vec3(0.5, 0.5, 0.6) + 0.1 * Vec3(u(rng), u(rng), u(rng)), 0.3, true));
        for (int i = 0; i < w.num_nodes(); ++i) {
          w.x[i] += 0.02 * Vec3(u(rng), u(rng), u(rng));
          w.m[i] = 0.01 * (2.0 + u(rng));
          w.inv_m[i] = 1.0 / w.m[i];
          w.v[i] = 0.1 * Vec3(u(rng), u(rng), u(rng));
        }
        ContactSpec s = exact_spec(0.25 * (1 + t % 3), t % 2 ? Region::half : Region::overlap);
        s.eliminator = rule.e;
        const double force = 1.0 + 0.5 * u(rng);
        if (rule.r == std::string("constant")) set_force_rule(s, "constant", {{"force", force}});
        else if (rule.r == std::string("penalty")) set_force_rule(s, "penalty", {{"stiffness", 300.0}});
        else set_force_rule(s, rule.r);
        s.two_sided = two_sided;
        Collision col(w, s);
        std::fill(w.f.begin(), w.f.end(), Vec3::Zero());
        const PairStep st = col.step(w, 1e-3);
        Vec3 net = Vec3::Zero();
        double total = 0.0;
        for (const Vec3& f : w.f) net += f, total += f.norm();
        INFO("try " << t << " two_sided " << two_sided);
        CHECK(net.norm() <= 1e-12 * std::max(1e-300, total));
        CHECK(st.beyond_band >= 0);
        for (std::size_t i = 0; i < col.pushes().size(); ++i) {
          if (!(col.magnitudes()[i] > 0.0)) continue;
          ++pushing;
          // Along the exact outward normal, or (plane) the plane's normal.
          if (rule.e == std::string("line")) CHECK(std::fabs(col.pushes()[i].n.norm() - 1.0) < 1e-12);
        }
      }
  CHECK(pushing > 1000);
}

TEST_CASE("voxel_exact: the depth penalty is the gradient of 1/2 k d^2", "[collision][voxel_exact]") {
  // Finite differences of the penalty energy sum over contacts against the forces applied, at
  // random states: the reactions on the triangle's vertices are barycentric and exact.
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int checked = 0;
  for (int t = 0; t < 20; ++t) {
    World w;
    add_body(w, "host", icosahedron(Vec3::Zero(), 1.0, false));
    Points g;
    for (int i = 0; i < 20; ++i) g.push_back(0.8 * Vec3(u(rng), u(rng), u(rng)));
    add_body(w, "guest", cloud(g));
    ContactSpec s = exact_spec(2.0);
    set_force_rule(s, "penalty", {{"stiffness", 50.0}});
    auto energy = [&](World& ww) {
      Collision c(ww, s);
      std::fill(ww.f.begin(), ww.f.end(), Vec3::Zero());
      c.step(ww, 1e-3);
      double e = 0.0;
      for (const Push& p : c.pushes()) e += 0.5 * rule_parameter(s, "stiffness") * std::max(0.0, p.depth) * std::max(0.0, p.depth);
      return e;
    };
    energy(w);
    const Points f = w.f;
    const double h = 1e-7;
    for (int node = 0; node < w.num_nodes(); ++node) {
      for (int a = 0; a < 3; ++a) {
        World wp = w, wm = w;
        wp.x[node][a] += h;
        wm.x[node][a] -= h;
        const double ep = energy(wp), em = energy(wm);
        const double grad = (ep - em) / (2 * h);
        INFO("try " << t << " node " << node << " axis " << a);
        CHECK(-grad == Approx(f[node][a]).margin(1e-6));
        checked += f[node][a] != 0.0;
      }
    }
  }
  CHECK(checked > 100);
}

TEST_CASE("voxel_exact: an undamped drop onto a pinned layer closes the energy audit", "[collision][voxel_exact][energy]") {
  const std::string text = R"({"name":"drop","time":{"dt":DT,"steps":0},
    "effects":["springs","gravity","pins","contact"],
    "gravity":[0,0,-9.81],
    "bodies":[{"name":"layer","shape":{"type":"box","min":[-0.03,-0.03,0],"max":[0.03,0.03,0.01],"cells":[12,12,2]},
               "material":{"density":1000,"youngs_modulus":3000},"pins":[{"side":"-z"}]},
              {"name":"ball","shape":{"type":"sphere","center":[0.0011,-0.0007,0.0185],"radius":0.008,
               "subdivisions":2,"fill":"volume"},
               "material":{"density":1000,"youngs_modulus":10000},"velocity":[0,0,-0.3]}],
    "contacts":[{"host":"layer","guest":"ball","detector":"voxel_exact","eliminator":"line",
                 "force":{"stiffness":400},"two_sided":true}]})";
  auto with_dt = [&](double dt) {
    std::string s = text;
    s.replace(s.find("DT"), 2, std::to_string(dt));
    return s;
  };
  Simulation probe(parse_scene(with_dt(1e-5), "drop.json"));
  Simulation sim(parse_scene(with_dt(0.3 * probe.critical_dt()), "drop.json"));
  double worst = 0.0, vz_min = 0.0, vz_max = -1.0;
  long long contacts = 0, beyond = 0;
  const Body& ball = sim.world().bodies[1];
  for (int s = 0; s < 6000; ++s) {
    sim.step();
    worst = std::max(worst, std::fabs(sim.energy().balance_error()));
    contacts += sim.pairs()[0].last.contacts;
    beyond += sim.pairs()[0].last.beyond_band;
    Vec3 v = Vec3::Zero();
    for (int i = ball.begin; i < ball.end; ++i) v += sim.world().v[i];
    v /= ball.size();
    vz_min = std::min(vz_min, v.z());
    if (contacts > 0) vz_max = std::max(vz_max, v.z());
  }
  INFO("worst |balance error| " << worst << ", contacts " << contacts << ", beyond the band " << beyond
                                << ", W_contact " << sim.energy().work_contact << ", vz " << vz_min << " .. " << vz_max);
  CHECK(contacts > 1000);
  CHECK(vz_max > 0.05);  // it bounced
  CHECK(worst < 0.01);
  CHECK(beyond >= 0);
}

TEST_CASE("voxel_exact: the same contacts and answers for any thread count", "[collision][voxel_exact][parallel]") {
  ThreadsGuard guard;
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  World w;
  add_body(w, "host", box_lattice(Vec3(0, 0, 0), Vec3(1, 1, 0.5), Vec3i(10, 10, 5)));
  Points g;
  for (int i = 0; i < 20000; ++i) g.push_back(Vec3(0.5, 0.5, 0.45) + 0.5 * Vec3(u(rng), u(rng), 0.3 * u(rng)));
  add_body(w, "guest", cloud(g));
  for (Region r : {Region::half, Region::full, Region::overlap}) {
    std::vector<std::vector<Contact>> got;
    std::vector<std::vector<double>> data;
    std::vector<int> beyond;
    for (int t : {1, 2, 3}) {
      set_threads(t);
      set_parallel_grain(t == 1 ? 0 : 1);
      Collision col(w, exact_spec(0.125, r));
      col.detect(w);
      col.detect(w);  // twice: the cached voxels of the first call must not leak into the second
      got.push_back(col.contacts());
      beyond.push_back(exact(col).beyond_band());
      data.emplace_back();
      for (const Contact& c : col.contacts()) {
        const VoxelExactDetector::Hit* h = exact(col).hit(c);
        REQUIRE(h);
        data.back().insert(data.back().end(), {h->depth, h->band, h->weight[0], h->weight[1], h->normal[0],
                                               h->normal[1], h->normal[2], h->within ? 1.0 : 0.0});
      }
    }
    REQUIRE(got[0].size() > 100);
    for (int k = 1; k < 3; ++k) {
      CHECK(got[k].size() == got[0].size());
      CHECK(std::equal(got[k].begin(), got[k].end(), got[0].begin(), got[0].end(),
                       [](const Contact& a, const Contact& b) { return a.guest == b.guest && a.key == b.key; }));
      CHECK(data[k] == data[0]);  // bit for bit
      CHECK(beyond[k] == beyond[0]);
    }
    CHECK(std::is_sorted(got[0].begin(), got[0].end(), [](const Contact& a, const Contact& b) { return a.guest < b.guest; }));
  }
}

TEST_CASE("voxel_exact: voxels with more candidates than a cache entry holds give the same answers",
          "[collision][voxel_exact][parallel]") {
  // A 12^3-cell lattice (864 surface faces): with 2 m voxels every block holds every face (the
  // overflow list, boxes per node); with 1/8 m voxels a few dozen (cached entries). Nodes inside
  // both bands get the same depth and triangle either way, with one thread or several.
  ThreadsGuard guard;
  std::mt19937 rng(12);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  World w;
  add_body(w, "host", box_lattice(Vec3(0, 0, 0), Vec3(1, 1, 1), Vec3i(12, 12, 12)));
  Points g;
  for (int i = 0; i < 3000; ++i) g.push_back(Vec3(u(rng), u(rng), u(rng)) * 1.2 - Vec3::Constant(0.1));
  add_body(w, "guest", cloud(g));
  int compared = 0;
  for (int t : {1, 2}) {
    set_threads(t);
    set_parallel_grain(t == 1 ? 0 : 1);
    Collision big(w, exact_spec(2.0)), small(w, exact_spec(0.125));
    big.detect(w);
    small.detect(w);
    for (const Contact& c : small.contacts()) {
      const VoxelExactDetector::Hit* hs = exact(small).hit(c);
      REQUIRE(hs);
      if (!hs->within) continue;
      const auto it = std::find_if(big.contacts().begin(), big.contacts().end(),
                                   [&](const Contact& b) { return b.guest == c.guest; });
      REQUIRE(it != big.contacts().end());
      const VoxelExactDetector::Hit* hb = exact(big).hit(*it);
      REQUIRE(hb);
      CHECK(hb->within);
      CHECK(hb->depth == Approx(hs->depth).epsilon(1e-14));
      ++compared;
    }
  }
  CHECK(compared > 500);
}

TEST_CASE("voxel_exact: the per-step path reuses its buffers", "[collision][voxel_exact]") {
  const auto box = box_lattice(Vec3(-1, -1, -1), Vec3(1, 1, 1), Vec3i(6, 6, 6));
  const auto ball = icosahedron(Vec3(0, 0, 3), 0.8, true);
  for (Region r : {Region::half, Region::full, Region::overlap}) {
    World w;
    add_body(w, "tissue", box);
    add_body(w, "tool", ball);
    ContactSpec s = exact_spec(0.5, r);
    set_force_rule(s, "penalty", {{"stiffness", 10.0}});
    s.two_sided = true;
    Collision col(w, s);
    col.step(w, 1e-3);
    const Contact* contacts = col.contacts().data();
    const long long grid_bytes = exact(col).grid().bytes();
    int total = 0;
    for (int step = 0; step < 200; ++step) {
      for (int i = w.bodies[1].begin; i < w.bodies[1].end; ++i) w.x[i].z() -= 0.02;
      std::fill(w.f.begin(), w.f.end(), Vec3::Zero());
      total += col.step(w, 1e-3).contacts;
      CHECK(col.contacts().data() == contacts);
      CHECK(exact(col).grid().bytes() == grid_bytes);
      for (const Vec3& f : w.f) REQUIRE(f.allFinite());
    }
    CHECK(total > 0);
    CHECK(col.rebuilds() == 0);
  }
}

TEST_CASE("voxel_exact: surface vertices listed, automatic size, refusals, registry", "[collision][voxel_exact]") {
  World w;
  add_body(w, "box", box_lattice(Vec3(0, 0, 0), Vec3(1, 1, 1), Vec3i(4, 4, 4)));
  add_body(w, "guest", cloud({Vec3(0.5, 0.5, 0.9)}));
  ContactSpec s = exact_spec(0.0);
  s.host_nodes = HostNodes::all;  // ignored: the lists hold the surface vertices
  Collision col(w, s);
  col.detect(w);
  CHECK(exact(col).grid().listed_nodes() == w.bodies[0].n_surface);
  // Automatic: the paper's size, the smallest power of two at or above the host's mean surface
  // edge (lattice edges 0.25 and face diagonals 0.354: mean above 0.25 -> 0.5), already above
  // L_max / sqrt(3) = 0.354 / 1.732 = 0.204, so not doubled: 0.5.
  CHECK(col.voxel_size() == 0.5);
  CHECK(exact(col).longest_edge() == Approx(0.25 * std::sqrt(2.0)).epsilon(1e-12));
  CHECK(std::string(col.detector().name()) == "voxel_exact");

  // A host without a surface, an open surface: refused at initialisation.
  World c;
  add_body(c, "cloud", cloud({Vec3(0, 0, 0), Vec3(1, 1, 1)}));
  add_body(c, "guest", cloud({Vec3(0.5, 0.5, 0.5)}));
  CHECK_THROWS_AS(Collision(c, exact_spec(0.5)), std::invalid_argument);
  auto open = box_lattice(Vec3(0, 0, 0), Vec3(1, 1, 1), Vec3i(2, 2, 2));
  open.faces.pop_back();
  World o;
  add_body(o, "open", open);
  add_body(o, "guest", cloud({Vec3(0.5, 0.5, 0.5)}));
  CHECK_THROWS_WITH(Collision(o, exact_spec(0.5)), Catch::Contains("2-manifold"));
  // Two-sided needs the guest's surface as well.
  ContactSpec two = exact_spec(0.5);
  two.two_sided = true;
  CHECK_THROWS_AS(Collision(w, two), std::invalid_argument);

  // In core, without the reference library: not an exact detector.
  REQUIRE(find_detector("voxel_exact"));
  CHECK_FALSE(find_detector("voxel_exact")->exact);
  CHECK(std::string(make_detector("voxel_exact", nullptr)->name()) == "voxel_exact");
  // Detectors without a band report none.
  ContactSpec v = exact_spec(0.25);
  v.detector = "voxel";
  Collision vc(w, v);
  vc.detect(w);
  CHECK(vc.detector().beyond_band() == -1);
}

TEST_CASE("voxel_exact: non-finite positions find nothing instead of failing", "[collision][voxel_exact]") {
  World w;
  add_body(w, "host", box_lattice(Vec3(0, 0, 0), Vec3(1, 1, 1), Vec3i(2, 2, 2)));
  add_body(w, "guest", cloud({Vec3(0.5, 0.5, 0.9), Vec3(0.4, 0.5, 0.9)}));
  for (Region r : {Region::half, Region::full, Region::overlap}) {
    World v = w;
    Collision col(v, exact_spec(0.5, r));
    CHECK(col.detect(v) == 2);
    v.x[v.bodies[1].begin] = Vec3(std::nan(""), 0, 0);
    CHECK(col.detect(v) == 1);
    v.x[1] = Vec3(std::numeric_limits<double>::infinity(), 0, 0);
    CHECK(col.detect(v) == 0);
  }
}

TEST_CASE("voxel_exact: a node deep inside, with no host vertex in its block, is undecided and counted",
          "[collision][voxel_exact]") {
  // A 8 x 8 x 8 lattice surface of 1 m (surface edges 0.125 m), voxel 0.125 m: a node at the centre
  // is 0.5 m from every face, its 3 x 3 x 3 block lists no host vertex. The grid cannot tell it
  // inside from outside: no contact, but counted beyond the band (undecided), not silently dropped.
  World w;
  add_body(w, "box", box_lattice(Vec3(0, 0, 0), Vec3(1, 1, 1), Vec3i(8, 8, 8)));
  const Points g = {Vec3(0.5013, 0.4987, 0.5021),   // deep inside: undecided
                    Vec3(0.5, 0.5, 0.99),           // near the top face inside: a contact
                    Vec3(1.5, 0.5, 0.5)};           // outside the box: nothing
  add_body(w, "guest", cloud(g));
  ContactSpec spec = exact_spec(0.125);
  Collision col(w, spec, nullptr);
  col.detect(w);
  const auto& det = exact(col);
  REQUIRE(col.contacts().size() == 1);
  CHECK(col.contacts()[0].guest == w.bodies[1].begin + 1);
  CHECK(det.undecided() == 1);
  CHECK(det.beyond_band() == 1);  // the undecided node (the contact is within its band)
  // With a voxel large enough for the centre's block to reach the faces, it is decided: a contact.
  ContactSpec coarse = exact_spec(0.25);
  Collision col2(w, coarse, nullptr);
  col2.detect(w);
  CHECK(exact(col2).undecided() == 0);
  CHECK(std::count_if(col2.contacts().begin(), col2.contacts().end(),
                      [&](const Contact& c) { return c.guest == w.bodies[1].begin; }) == 1);
}
