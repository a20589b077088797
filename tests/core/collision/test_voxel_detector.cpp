// The voxel detector against a brute-force oracle that recomputes the grid geometry from the
// formulas documented in initializer.hpp / voxel_data.hpp and checks every guest node against
// every host node.
#include "core/collision/responses/force_rule.hpp"
#include "core/scene/scene.hpp"
#include "core/collision/collision.hpp"
#include "core/collision/detectors/voxel.hpp"
#include "tests/core/collision/collision_test_worlds.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

using namespace harness;
using harness::test::add_body;
using harness::test::cloud;

namespace {

// Independent of round_down_pow2: halve / double until it fits.
double oracle_pow2(double v) {
  double p = 1.0;
  while (p > v) p /= 2.0;
  while (p * 2.0 <= v) p *= 2.0;
  return p;
}

void oracle_bounds(const World& w, int body, Vec3& lo, Vec3& hi) {
  const Body& b = w.bodies[body];
  const double inf = std::numeric_limits<double>::infinity();
  lo = Vec3(inf, inf, inf);
  hi = -lo;
  for (int i = b.begin; i < b.end; ++i)
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], w.x[i][a]);
      hi[a] = std::max(hi[a], w.x[i][a]);
    }
}

// What the region was last built for, and the rule that rebuilds it.
struct OracleState {
  double v = 0.0;
  Vec3 H = Vec3::Zero();
  int axis = -1, sign = 1;
  int rebuilds = 0;

  void build(const World& w, const ContactSpec& s, const Vec3& h) {
    H = h;
    axis = -1;
    sign = 1;
    if (s.region != Region::half) return;
    Vec3 lo, hi, glo, ghi;
    oracle_bounds(w, s.host, lo, hi);
    oracle_bounds(w, s.guest, glo, ghi);
    const Vec3 d = 0.5 * (glo + ghi) - 0.5 * (lo + hi);
    double best = 0.0;
    for (int a = 0; a < 3; ++a) {
      double r = 0.0;
      if (H[a] > 0.0) r = std::fabs(d[a]) / H[a];
      else if (d[a] != 0.0) r = std::numeric_limits<double>::infinity();
      if (r > best) best = r, axis = a;
    }
    if (axis >= 0) sign = d[axis] < 0.0 ? -1 : 1;
  }
};

struct OracleGrid {
  Vec3 c;
  double L[3], U[3];  // cells [L, U) counted from c
  bool empty = false;
};

OracleGrid oracle_grid(const World& w, const ContactSpec& s, OracleState& st) {
  Vec3 lo, hi;
  oracle_bounds(w, s.host, lo, hi);
  OracleGrid g;
  g.c = 0.5 * (lo + hi);
  const Vec3 h = 0.5 * (hi - lo);
  bool grew = false;
  for (int a = 0; a < 3; ++a) grew = grew || h[a] > st.H[a] + st.v;
  if (grew) {
    st.build(w, s, h);
    ++st.rebuilds;
  }
  const double m = s.margin, v = st.v;
  for (int a = 0; a < 3; ++a) {
    const double n = std::floor(st.H[a] / v) + 2.0;
    g.L[a] = -n - m;
    g.U[a] = n + m;
  }
  if (st.axis >= 0) {
    const int a = st.axis;
    const double n = std::floor(st.H[a] / v) + 2.0;
    if (st.sign > 0) g.L[a] = -m, g.U[a] = n + m;
    else g.L[a] = -n - m, g.U[a] = m;
  }
  if (s.region == Region::overlap) {
    Vec3 glo, ghi;
    oracle_bounds(w, s.guest, glo, ghi);
    for (int a = 0; a < 3; ++a) {
      const double l = std::max(std::floor((lo[a] - g.c[a]) / v), std::floor((glo[a] - g.c[a]) / v)) - m;
      const double u = std::min(std::floor((hi[a] - g.c[a]) / v), std::floor((ghi[a] - g.c[a]) / v)) + m + 1;
      g.L[a] = std::max(g.L[a], l);
      g.U[a] = std::min(g.U[a], u);
      if (!(g.U[a] > g.L[a])) g.empty = true;
    }
  }
  return g;
}

// Per-axis cell of p counted from L, or false when outside.
bool oracle_cell(const OracleGrid& g, double v, const Vec3& p, double k[3]) {
  if (g.empty) return false;
  for (int a = 0; a < 3; ++a) {
    const double t = std::floor((p[a] - g.c[a]) / v);
    if (!(t >= g.L[a] && t < g.U[a])) return false;
    k[a] = t - g.L[a];
  }
  return true;
}

std::vector<int> oracle_listed(const World& w, const ContactSpec& s) {
  const Body& b = w.bodies[s.host];
  const int end = s.host_nodes == HostNodes::surface ? b.begin + b.n_surface : b.end;
  std::vector<int> r;
  for (int i = b.begin; i < end; ++i) r.push_back(i);
  return r;
}

std::vector<Contact> oracle_contacts(const World& w, const ContactSpec& s, const OracleGrid& g,
                                     double v) {
  std::vector<Contact> out;
  const std::vector<int> hosts = oracle_listed(w, s);
  const Body& gb = w.bodies[s.guest];
  const double D0 = g.U[0] - g.L[0], D1 = g.U[1] - g.L[1];
  for (int i = gb.begin; i < gb.end; ++i) {
    double k[3];
    if (!oracle_cell(g, v, w.x[i], k)) continue;
    for (int h : hosts) {
      double kh[3];
      if (oracle_cell(g, v, w.x[h], kh) && kh[0] == k[0] && kh[1] == k[1] && kh[2] == k[2]) {
        out.push_back(Contact{i, static_cast<int>(k[0] + D0 * (k[1] + D1 * k[2]))});
        break;
      }
    }
  }
  return out;
}

// The k nearest listed host nodes to guest g in the cells within `reach` of its cell.
std::vector<int> oracle_nearest(const World& w, const ContactSpec& s, const OracleGrid& g,
                                double v, int guest, int k, int reach) {
  double kg[3] = {0.0, 0.0, 0.0};
  oracle_cell(g, v, w.x[guest], kg);
  std::vector<std::pair<double, int>> cand;
  for (int h : oracle_listed(w, s)) {
    double kh[3];
    if (!oracle_cell(g, v, w.x[h], kh)) continue;
    bool near = true;
    for (int a = 0; a < 3; ++a) near = near && std::fabs(kh[a] - kg[a]) <= reach;
    if (near) cand.emplace_back((w.x[h] - w.x[guest]).squaredNorm(), h);
  }
  std::sort(cand.begin(), cand.end());
  std::vector<int> r;
  for (int i = 0; i < k && i < static_cast<int>(cand.size()); ++i) r.push_back(cand[i].second);
  return r;
}

bool same(const std::vector<Contact>& a, const std::vector<Contact>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (a[i].guest != b[i].guest || a[i].key != b[i].key) return false;
  return true;
}

std::vector<int> guests_of(const std::vector<Contact>& c) {
  std::vector<int> r;
  for (const Contact& x : c) r.push_back(x.guest);
  return r;
}

struct RandomCase {
  World w;
  ContactSpec spec = contact_spec_defaults();
  double v = 0.0;
};

RandomCase random_case(std::mt19937& rng) {
  std::uniform_real_distribution<double> U(0.0, 1.0);
  auto uni = [&](double a, double b) { return a + (b - a) * U(rng); };
  auto coin = [&](double p) { return U(rng) < p; };
  auto pick = [&](int a, int b) { return std::uniform_int_distribution<int>(a, b)(rng); };

  RandomCase rc;
  const double v_req = coin(0.3) ? std::ldexp(1.0, pick(-3, 1)) : std::exp2(uni(-3.0, 1.5));
  const double v = oracle_pow2(v_req);
  rc.v = v;
  const bool dyadic = coin(0.4);
  // Dyadic mode: coordinates on a lattice of v/4, so many nodes sit exactly on voxel faces.
  auto snap = [&](double x) { return dyadic ? std::round(x / (v / 4)) * (v / 4) : x; };

  const int nh = pick(1, 40), ng = pick(1, 40);
  const Vec3 ch(uni(-4, 4), uni(-4, 4), uni(-4, 4));
  Vec3 sh;
  for (int a = 0; a < 3; ++a) sh[a] = coin(0.1) ? 0.0 : uni(0.0, 6.0 * v);
  Points host(nh), guest(ng);
  for (auto& p : host)
    for (int a = 0; a < 3; ++a) p[a] = snap(ch[a] + uni(-sh[a], sh[a]));
  Vec3 cg, sg;
  for (int a = 0; a < 3; ++a) {
    cg[a] = ch[a] + uni(-2.0, 2.0) * (sh[a] + v);
    sg[a] = uni(0.0, 4.0 * v);
  }
  Vec3 lo = host[0], hi = host[0];
  for (const auto& p : host) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  const Vec3 c = 0.5 * (lo + hi);
  for (auto& p : guest) {
    const double r = U(rng);
    if (r < 0.15) {
      p = host[pick(0, nh - 1)];  // coincides with a host node
    } else if (r < 0.25) {
      for (int a = 0; a < 3; ++a) p[a] = c[a] + pick(-8, 8) * v;  // on voxel faces (near-exact)
    } else if (r < 0.30) {
      p = cg + Vec3(uni(-1, 1), uni(-1, 1), uni(-1, 1)) * 1000.0 * v;  // far outside
    } else if (r < 0.31) {
      p = Vec3(uni(-1, 1), uni(-1, 1), uni(-1, 1)) * 1e300;  // huge
    } else {
      for (int a = 0; a < 3; ++a) p[a] = snap(cg[a] + uni(-sg[a], sg[a]));
    }
  }
  add_body(rc.w, "host", cloud(host, coin(0.3) ? pick(0, nh) : nh));
  add_body(rc.w, "guest", cloud(guest));
  rc.spec.host = 0;
  rc.spec.guest = 1;
  rc.spec.voxel_size = v_req;
  rc.spec.region = static_cast<Region>(pick(0, 2));
  rc.spec.margin = pick(0, 2);
  rc.spec.host_nodes = coin(0.3) ? HostNodes::surface : HostNodes::all;
  return rc;
}

}  // namespace

TEST_CASE("voxel detector equals the brute-force oracle on random configurations",
          "[collision][voxel][oracle]") {
  std::mt19937 rng(20130312);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  int configurations = 0, checked_steps = 0, contacts = 0, rebuilds = 0, face_nodes = 0;
  int nearest_checked = 0;
  for (int t = 0; t < 2000; ++t) {
    RandomCase rc = random_case(rng);
    World& w = rc.w;
    const ContactSpec& s = rc.spec;
    INFO("case " << t << " region " << static_cast<int>(s.region) << " margin " << s.margin
                 << " voxel " << rc.v);
    VoxelDetector det;
    det.initialize(w, s);
    REQUIRE(det.voxel_size() == rc.v);
    // Same pair with the full and the overlap region: overlap must find the same guests.
    ContactSpec sf = s, so = s;
    sf.region = Region::full;
    so.region = Region::overlap;
    VoxelDetector dfull, dover;
    dfull.initialize(w, sf);
    dover.initialize(w, so);

    OracleState st;
    st.v = rc.v;
    {
      Vec3 lo, hi;
      oracle_bounds(w, s.host, lo, hi);
      st.build(w, s, 0.5 * (hi - lo));
    }
    std::vector<Contact> got;
    got.reserve(w.bodies[1].size());
    for (int phase = 0; phase < 2; ++phase) {
      if (phase == 1) {
        if (U(rng) < 0.4) break;
        // Deform the host (grow or shrink about a point) and move the guest.
        const double sc = 0.5 + 1.7 * U(rng);
        const Vec3 p(U(rng), U(rng), U(rng)), tr = Vec3(U(rng), U(rng), U(rng)) - Vec3::Constant(0.5);
        for (int i = w.bodies[0].begin; i < w.bodies[0].end; ++i) w.x[i] = p + sc * (w.x[i] - p) + tr;
        for (int i = w.bodies[1].begin; i < w.bodies[1].end; ++i) w.x[i] += tr * U(rng);
      }
      const OracleGrid g = oracle_grid(w, s, st);
      const std::vector<Contact> want = oracle_contacts(w, s, g, rc.v);
      const Contact* before = got.data();
      det.detect(w, got);
      CHECK(got.data() == before);  // the caller's reserved buffer is reused
      ++checked_steps;
      REQUIRE(same(got, want));
      CHECK(det.rebuilds() == st.rebuilds);
      contacts += static_cast<int>(got.size());

      std::vector<Contact> cf, co;
      dfull.detect(w, cf);
      dover.detect(w, co);
      CHECK(guests_of(cf) == guests_of(co));

      for (int i = w.bodies[1].begin; i < w.bodies[1].end; ++i)
        for (int a = 0; a < 3; ++a) {
          const double q = (w.x[i][a] - g.c[a]) / rc.v;
          if (std::isfinite(q) && q == std::floor(q)) ++face_nodes;
        }
      for (const Contact& c : got) {
        int out[4] = {-1, -1, -1, -1};
        const int n1 = det.nearest_hosts(w, c, 1, out);
        REQUIRE(n1 == 1);
        CHECK(std::vector<int>(out, out + 1) == oracle_nearest(w, s, g, rc.v, c.guest, 1, 0));
        const int n3 = det.nearest_hosts(w, c, 3, out);
        const std::vector<int> want3 = oracle_nearest(w, s, g, rc.v, c.guest, 3, 1);
        CHECK(std::vector<int>(out, out + n3) == want3);
        ++nearest_checked;
      }
    }
    rebuilds += st.rebuilds;
    ++configurations;
  }
  CHECK(configurations >= 1000);
  // The generator must actually exercise the interesting cases.
  CHECK(contacts > 3000);
  CHECK(rebuilds > 50);
  CHECK(face_nodes > 1000);
  CHECK(nearest_checked == contacts);
  WARN("oracle: " << configurations << " configurations, " << checked_steps << " steps, "
                  << contacts << " contacts, " << rebuilds << " rebuilds, " << face_nodes
                  << " guest coordinates on voxel faces");
}

TEST_CASE("contacts do not change when host and guest translate together",
          "[collision][voxel]") {
  // Coordinates on a lattice of 2^-8 m, translations too: every subtraction is exact, so the
  // grid attached to the host must give identical contacts and keys.
  std::mt19937 rng(5);
  std::uniform_int_distribution<int> q(-300, 300), tq(-4000, 4000);
  const double unit = std::ldexp(1.0, -8);
  for (Region region : {Region::half, Region::full, Region::overlap}) {
    for (int t = 0; t < 50; ++t) {
      Points host(30), guest(30);
      for (auto& p : host) p = Vec3(q(rng), q(rng), q(rng)) * unit;
      for (auto& p : guest) p = Vec3(q(rng) + 200, q(rng), q(rng)) * unit;
      World w;
      add_body(w, "host", cloud(host));
      add_body(w, "guest", cloud(guest));
      ContactSpec s = contact_spec_defaults();
      s.host = 0;
      s.guest = 1;
      s.voxel_size = 0.3;  // -> 0.25, so the translations below are not multiples of it
      s.region = region;
      VoxelDetector det;
      det.initialize(w, s);
      std::vector<Contact> a, b;
      det.detect(w, a);
      const Vec3 shift = Vec3(tq(rng), tq(rng), tq(rng)) * unit;
      for (auto& p : w.x) p += shift;
      det.detect(w, b);
      CHECK(same(a, b));
      CHECK(det.rebuilds() == 0);
    }
  }
  // A world-fixed grid would change: check that the example is not trivial.
  Points host{Vec3(0, 0, 0), Vec3(1, 1, 1)}, guest{Vec3(0.2, 0.2, 0.2)};
  World w;
  add_body(w, "host", cloud(host));
  add_body(w, "guest", cloud(guest));
  ContactSpec s = contact_spec_defaults();
  s.host = 0;
  s.guest = 1;
  s.voxel_size = 0.5;
  s.region = Region::full;
  Collision col(w, s);
  CHECK(col.detect(w) == 1);
  for (auto& p : w.x) p += Vec3(0.375, -0.125, 7.0);
  CHECK(col.detect(w) == 1);
  w.x[2] += Vec3(0.5, 0, 0);  // the guest alone moves into an empty voxel
  CHECK(col.detect(w) == 0);
}

TEST_CASE("the region is rebuilt when the host outgrows it", "[collision][voxel]") {
  World w;
  const auto box = harness::test::box_lattice(Vec3(-1, -1, -1), Vec3(1, 1, 1), Vec3i(4, 4, 4));
  add_body(w, "implant", box);
  add_body(w, "tissue", cloud({Vec3(0, 0, 3)}));
  ContactSpec s = contact_spec_defaults();
  s.host = 0;
  s.guest = 1;
  s.voxel_size = 0.25;
  s.region = Region::half;
  s.margin = 0;
  VoxelDetector det;
  det.initialize(w, s);
  CHECK(det.initializer().half_axis() == 2);
  CHECK(det.initializer().half_sign() == 1);
  std::vector<Contact> c;
  const Points rest(w.x.begin(), w.x.begin() + w.bodies[0].end);
  auto inflate = [&](double f) {
    for (int i = 0; i < w.bodies[0].end; ++i) w.x[i] = f * rest[i];
  };
  inflate(1.2);  // h = 1.2 <= H + v = 1.25: still inside the region
  det.detect(w, c);
  CHECK(det.rebuilds() == 0);
  // All host nodes in the upper half (z >= 0) are still listed.
  CHECK(det.grid().listed_nodes() == 5 * 5 * 3);
  inflate(1.3);  // h = 1.3 > 1.25
  det.detect(w, c);
  CHECK(det.rebuilds() == 1);
  CHECK(det.initializer().built_half_extents().isApprox(Vec3::Constant(1.3)));
  CHECK(det.grid().listed_nodes() == 5 * 5 * 3);
  inflate(0.5);  // shrinking never rebuilds
  det.detect(w, c);
  CHECK(det.rebuilds() == 1);
  // The grown implant reaches the tissue node.
  w.x[w.bodies[1].begin] = Vec3(0.01, 0.01, 2.9);
  inflate(2.9);
  det.detect(w, c);
  CHECK(det.rebuilds() == 2);
  REQUIRE(c.size() == 1);
  CHECK(c[0].guest == w.bodies[1].begin);
}

TEST_CASE("half region faces the guest", "[collision][voxel]") {
  const Points host{Vec3(-1, -2, -4), Vec3(1, 2, 4)};
  struct Case { Vec3 guest; int axis, sign; };
  // Offsets relative to the half extents (1, 2, 4): the largest ratio wins.
  for (const Case& k : {Case{Vec3(1.5, 0, 0), 0, 1}, Case{Vec3(-1.5, 3.2, 0), 1, 1},
                        Case{Vec3(0.9, 0, -3.7), 2, -1}, Case{Vec3(0, -2.5, 4.9), 1, -1},
                        Case{Vec3(0, 0, 0), -1, 1}}) {
    World w;
    add_body(w, "host", cloud(host));
    add_body(w, "guest", cloud({k.guest}));
    ContactSpec s = contact_spec_defaults();
    s.host = 0;
    s.guest = 1;
    s.voxel_size = 0.5;
    VoxelDetector det;
    det.initialize(w, s);
    CHECK(det.initializer().half_axis() == k.axis);
    if (k.axis >= 0) CHECK(det.initializer().half_sign() == k.sign);
  }
  // A flat host (zero extent on z): any offset along z wins.
  World w;
  add_body(w, "sheet", cloud({Vec3(-5, -5, 0), Vec3(5, 5, 0)}));
  add_body(w, "ball", cloud({Vec3(4, 4, -0.1)}));
  ContactSpec s = contact_spec_defaults();
  s.host = 0;
  s.guest = 1;
  s.voxel_size = 1;
  VoxelDetector det;
  det.initialize(w, s);
  CHECK(det.initializer().half_axis() == 2);
  CHECK(det.initializer().half_sign() == -1);
}

TEST_CASE("surface host nodes fill only the surface vertices", "[collision][voxel]") {
  // Node 0 is the only surface vertex; node 1 is interior.
  World w;
  add_body(w, "host", cloud({Vec3(0.1, 0.1, 0.1), Vec3(0.6, 0.6, 0.6), Vec3(-2, -2, -2), Vec3(2, 2, 2)}, 1));
  add_body(w, "guest", cloud({Vec3(0.7, 0.7, 0.7), Vec3(0.2, 0.2, 0.2)}));
  ContactSpec s = contact_spec_defaults();
  s.host = 0;
  s.guest = 1;
  s.voxel_size = 0.5;
  s.region = Region::full;
  s.host_nodes = HostNodes::all;
  Collision all(w, s);
  all.detect(w);
  CHECK(guests_of(all.contacts()) == std::vector<int>{4, 5});
  s.host_nodes = HostNodes::surface;
  Collision surf(w, s);
  surf.detect(w);
  CHECK(guests_of(surf.contacts()) == std::vector<int>{5});
}

TEST_CASE("voxel size: automatic choice and the capacity cap", "[collision][voxel]") {
  World w;
  add_body(w, "host", cloud({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)}));
  add_body(w, "guest", cloud({Vec3(0, 0, 2)}));
  ContactSpec s = contact_spec_defaults();
  s.host = 0;
  s.guest = 1;
  s.voxel_size = 0.0;
  // No surface, no springs: largest extent / cbrt(nodes) = 1 / 1.587 = 0.63 -> 1 (the smallest
  // power of two at or above the spacing).
  CHECK(resolve_voxel_size(w, s) == 1.0);
  // With springs: the mean rest length (0.3 + 0.5) / 2 = 0.4 -> 0.5.
  w.springs.ends = {Edge{0, 1}, Edge{0, 2}};
  w.springs.rest = {0.3, 0.5};
  w.springs.body = {0, 0};
  w.bodies[0].spring_begin = 0;
  w.bodies[0].spring_end = 2;
  CHECK(resolve_voxel_size(w, s) == 0.5);
  {
    Collision col(w, s);
    CHECK(col.voxel_size() == 0.5);
  }
  s.voxel_size = -1.0;
  CHECK_THROWS_AS(Collision(w, s), std::invalid_argument);
  s.voxel_size = std::nan("");
  CHECK_THROWS_AS(Collision(w, s), std::invalid_argument);

  // 1 m host (H = 0.5), 1/1024 m voxels: 2 * (514 + 1) cells per axis, about 1.1e9 voxels.
  s.voxel_size = 1.0 / 1024;
  s.region = Region::full;
  try {
    Collision col(w, s);
    FAIL("expected the capacity cap");
  } catch (const std::invalid_argument& e) {
    const std::string msg = e.what();
    CHECK(msg.find("cap") != std::string::npos);
    CHECK(msg.find("host") != std::string::npos);
  }
  // Huge coordinates must fail the cap, not overflow.
  World big;
  add_body(big, "host", cloud({Vec3(-1e300, 0, 0), Vec3(1e300, 0, 0)}));
  add_body(big, "guest", cloud({Vec3(0, 0, 0)}));
  s.voxel_size = 1.0;
  CHECK_THROWS_AS(Collision(big, s), std::invalid_argument);

  // Outgrowing the cap during the run is a runtime failure.
  s.voxel_size = 1.0 / 64;
  Collision col(w, s);
  for (int i = 0; i < 4; ++i) w.x[i] *= 100.0;
  CHECK_THROWS_AS(col.detect(w), std::runtime_error);
}

TEST_CASE("bad pairs and the detector registry", "[collision][voxel]") {
  World w;
  add_body(w, "a", cloud({Vec3(0, 0, 0), Vec3(1, 1, 1)}));
  add_body(w, "b", cloud({Vec3(0, 0, 0)}));
  ContactSpec s = contact_spec_defaults();
  s.host = 0;
  s.guest = 0;
  CHECK_THROWS_AS(Collision(w, s), std::invalid_argument);
  s.guest = 5;
  CHECK_THROWS_AS(Collision(w, s), std::invalid_argument);
  s.guest = 1;
  s.margin = -1;
  CHECK_THROWS_AS(Collision(w, s), std::invalid_argument);
  s.margin = 1;
  set_force_rule(s, "constant", {{"force", 1.0}});
  s.force_parameters = {std::numeric_limits<double>::infinity()};  // a constant force that is not finite
  CHECK_THROWS_AS(Collision(w, s), std::invalid_argument);
  s.force_parameters = {1.0};
  // An exact detector without the reference library's maker: refused, naming the library.
  s.detector = "cgal";
  CHECK_THROWS_WITH(Collision(w, s), Catch::Contains("reference library"));
  CHECK(std::string(make_detector("voxel", nullptr)->name()) == "voxel");
  for (const DetectorDef& d : detectors()) {
    if (d.exact) CHECK_THROWS_AS(make_detector(d.name, nullptr), std::invalid_argument);
    else CHECK(std::string(make_detector(d.name, nullptr)->name()) == d.name);  // the maker makes that one
  }
  s.detector = "voxel";
  Collision col(w, s);
  CHECK(col.detect(w) == 1);
}

TEST_CASE("non-finite positions find nothing instead of failing", "[collision][voxel]") {
  World w;
  add_body(w, "host", cloud({Vec3(0, 0, 0), Vec3(1, 1, 1)}));
  add_body(w, "guest", cloud({Vec3(0.1, 0.1, 0.1), Vec3(0.2, 0.1, 0.1)}));
  ContactSpec s = contact_spec_defaults();
  s.host = 0;
  s.guest = 1;
  s.voxel_size = 0.5;
  for (Region r : {Region::half, Region::full, Region::overlap}) {
    s.region = r;
    World v = w;
    Collision col(v, s);
    CHECK(col.detect(v) == 2);
    v.x[3] = Vec3(std::nan(""), 0, 0);  // one bad guest node: only it is dropped
    CHECK(col.detect(v) == 1);
    v.x[1] = Vec3(std::numeric_limits<double>::infinity(), 0, 0);  // a bad host: nothing
    CHECK(col.detect(v) == 0);
    CHECK(col.rebuilds() == 0);
  }
}

TEST_CASE("the per-step path reuses its buffers", "[collision][voxel]") {
  // A guest sweeping through a host, 200 steps, every region: the contact list and the grid's
  // storage must never move or grow (no reallocation after construction).
  const auto box = harness::test::box_lattice(Vec3(-1, -1, -1), Vec3(1, 1, 1), Vec3i(6, 6, 6));
  const auto ball = harness::test::icosahedron(Vec3(0, 0, 3), 0.8, true);
  for (Region r : {Region::half, Region::full, Region::overlap}) {
    for (const std::string e : {"line", "plane"}) {
      World w;
      add_body(w, "tissue", box);
      add_body(w, "tool", ball);
      ContactSpec s = contact_spec_defaults();
      s.host = 0;
      s.guest = 1;
      s.voxel_size = 0.3;
      s.region = r;
      s.eliminator = e;
      set_force_rule(s, "auto");
      Collision col(w, s);
      col.step(w, 1e-3);
      const Contact* contacts = col.contacts().data();
      const auto& det = dynamic_cast<const VoxelDetector&>(col.detector());
      const long long grid_bytes = det.grid().bytes();
      int total = 0;
      for (int step = 0; step < 200; ++step) {
        for (int i = w.bodies[1].begin; i < w.bodies[1].end; ++i) w.x[i].z() -= 0.02;
        std::fill(w.f.begin(), w.f.end(), Vec3::Zero());
        const PairStep st = col.step(w, 1e-3);
        total += st.contacts;
        CHECK(col.contacts().data() == contacts);
        CHECK(det.grid().bytes() == grid_bytes);
        for (const Vec3& f : w.f) REQUIRE(f.allFinite());
      }
      CHECK(total > 0);
      CHECK(col.rebuilds() == 0);
    }
  }
}
