// Accuracy both ways (core/run/compare.hpp): signed distances and gaps on analytic
// configurations, the error of a hand-computed case, a run compared with itself.
#include "core/scene/scene.hpp"
#include "core/run/run_scene.hpp"
#include "core/run/compare.hpp"
#include "reference/reference.hpp"
#include "tests/reference/reference_test_worlds.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>

#include <unistd.h>

using namespace harness;
using namespace harness::reftest;
namespace fs = std::filesystem;

namespace {
ReferenceSpec cgal_only() {
  ReferenceSpec s = reference_spec_defaults();
  s.cgal = true;
  return s;
}
}  // namespace

TEST_CASE("signed distance: two spheres at known distances", "[accuracy][cgal]") {
  const double R = 1.0;
  for (double D : {2.5, 2.05, 1.8}) {  // apart, nearly touching, overlapping
    World w;
    ContactSpec pair = contact_spec_defaults();
    pair.host = add_body(w, "a", icosphere(Vec3::Zero(), R, 3));
    pair.guest = add_body(w, "b", icosphere(Vec3(D, 0, 0), R, 3));
    ReferenceMeasurer m(w, pair, cgal_only());
    Measurement out;
    m.measure(w, pair, {}, out);
    REQUIRE(out.sd_guest);
    REQUIRE(out.sd_host);
    // An icosphere of 3 subdivisions lies inside its sphere by at most its sagitta: vertices are
    // on the sphere, faces up to ~0.5 % of R inside.
    const double sagitta = 0.005 * R;
    const Body& b = w.bodies[pair.guest];
    double nearest = 1e9;
    for (int s = 0; s < b.n_surface; ++s) {
      const Vec3& p = w.x[b.begin + s];
      const double analytic = p.norm() - R;  // distance to sphere a's surface, negative inside
      INFO("D " << D << " vertex " << s << ": measured " << (*out.sd_guest)[s] << ", analytic " << analytic);
      // Farther from a's bounding box [-R, R]^3 than a quarter of its diagonal (sqrt(3) R / 2):
      // the distance to the box, a lower bound (the measurement spends no exact search there).
      const double box = (p.cwiseAbs() - Vec3::Constant(R)).cwiseMax(0.0).norm();
      if (box > 0.25 * 2.0 * std::sqrt(3.0) * R) {
        CHECK((*out.sd_guest)[s] == Approx(box).margin(1e-12));
        CHECK((*out.sd_guest)[s] <= analytic + sagitta);
        continue;
      }
      CHECK((*out.sd_guest)[s] >= analytic - 1e-12);  // the polyhedron is inside the sphere
      CHECK((*out.sd_guest)[s] <= analytic + sagitta);
      nearest = std::min(nearest, (*out.sd_guest)[s]);
    }
    CHECK(nearest == Approx(D - 2 * R).margin(sagitta));
  }
}

TEST_CASE("signed distance and gap: a cube above a layer at a known gap", "[accuracy][cgal]") {
  for (double g : {0.05, 0.0, -0.1}) {
    World w;
    ContactSpec pair = contact_spec_defaults();
    pair.host = add_body(w, "layer", box_surface(Vec3(-1, -1, -0.5), Vec3(2, 2, 0.0), Vec3i(6, 6, 1)));
    pair.guest = add_body(w, "cube", box_surface(Vec3(0, 0, g), Vec3(1, 1, 1 + g), Vec3i(4, 4, 4)));
    ReferenceMeasurer m(w, pair, cgal_only());
    Measurement out;
    m.measure(w, pair, {}, out);
    const Body& c = w.bodies[pair.guest];
    for (int s = 0; s < c.n_surface; ++s) {
      const Vec3& p = w.x[c.begin + s];
      if (std::fabs(p.z() - g) > 1e-12) continue;  // the bottom face: at signed distance g exactly
      CHECK((*out.sd_guest)[s] == Approx(g).margin(1e-12));
    }
    // The gap of this state against the touching one (g = 0) is g over the bottom face.
    if (g > 0.0) {
      World w0;
      ContactSpec p0;
      p0.host = add_body(w0, "layer", box_surface(Vec3(-1, -1, -0.5), Vec3(2, 2, 0.0), Vec3i(6, 6, 1)));
      p0.guest = add_body(w0, "cube", box_surface(Vec3(0, 0, 0), Vec3(1, 1, 1), Vec3i(4, 4, 4)));
      ReferenceMeasurer m0(w0, p0, cgal_only());
      Measurement o0;
      m0.measure(w0, p0, {}, o0);
      const SurfaceState ref = surface_state(w0, 0, 0.0, {*o0.sd_host, *o0.sd_guest});
      const SurfaceState now = surface_state(w, 0, 0.0, {*out.sd_host, *out.sd_guest});
      const ReferenceErrors e = Comparison::errors(now, ref, pair.host, pair.guest);
      CHECK(e.touching >= 25);  // the bottom face's 25 vertices (and layer vertices on it)
      CHECK(e.gap_max == Approx(g).margin(1e-12));
      CHECK(e.pos_err_max == Approx(g).margin(1e-12));
      CHECK(e.depth_max == 0.0);
    }
  }
}

// Measurer::needs: asked for only the distances the figures read (nodes inside, nodes reported,
// nodes the reference has touching), the measurement gives those exactly and a lower bound >= 0
// elsewhere, and the gap, depth and error against the reference are those of a full measurement.
TEST_CASE("signed distance: exact where the figures read it, a lower bound elsewhere", "[accuracy][cgal]") {
  auto scene = [](World& w, ContactSpec& p, double g) {
    p.host = add_body(w, "layer", box_surface(Vec3(-1, -1, -0.5), Vec3(2, 2, 0.0), Vec3i(6, 6, 1)));
    p.guest = add_body(w, "cube", box_surface(Vec3(0, 0, g), Vec3(1, 1, 1 + g), Vec3i(4, 4, 4)));
  };
  World w0;
  ContactSpec p0;
  scene(w0, p0, 0.0);
  ReferenceMeasurer m0(w0, p0, cgal_only());
  Measurement o0;
  m0.measure(w0, p0, {}, o0);
  const SurfaceState ref = surface_state(w0, 0, 0.0, {*o0.sd_host, *o0.sd_guest});
  for (double g : {0.05, -0.1}) {  // apart (a gap over the bottom face), overlapping (a depth)
    World w;
    ContactSpec pair = contact_spec_defaults();
    scene(w, pair, g);
    ReferenceMeasurer all(w, pair, cgal_only()), some(w, pair, cgal_only());
    const Body& c = w.bodies[pair.guest];
    const std::vector<Contact> reported = {Contact{c.begin + c.n_surface - 1, 0}};  // a reported node: the cube's last vertex
    some.needs.all = false;
    some.needs.touch = kTouchTolerance;
    some.needs.ref_host = &ref.sd[pair.host];
    some.needs.ref_guest = &ref.sd[pair.guest];
    Measurement a, s;
    all.measure(w, pair, reported, a);
    some.measure(w, pair, reported, s);
    CHECK(s.true_pen_guest == a.true_pen_guest);
    CHECK(s.max_depth == a.max_depth);
    int exact = 0, bounded = 0;
    for (int k = 0; k < c.n_surface; ++k) {
      const double full = (*a.sd_guest)[k], part = (*s.sd_guest)[k];
      const bool needed = (*a.pen_guest)[k] || std::fabs(ref.sd[pair.guest][k]) <= kTouchTolerance || k == c.n_surface - 1;
      if (needed) {
        CHECK(part == full);
        ++exact;
      } else {
        CHECK(part >= 0.0);
        CHECK(part <= full + 1e-15);  // (for a box-shaped host the box distance is exact)
        ++bounded;
      }
    }
    CHECK(exact >= 26);    // the bottom face's 25 vertices and the reported one
    CHECK(bounded > 0);    // the rest of the cube got its lower bound
    const SurfaceState na = surface_state(w, 0, 0.0, {*a.sd_host, *a.sd_guest});
    const SurfaceState ns = surface_state(w, 0, 0.0, {*s.sd_host, *s.sd_guest});
    const ReferenceErrors ea = Comparison::errors(na, ref, pair.host, pair.guest);
    const ReferenceErrors es = Comparison::errors(ns, ref, pair.host, pair.guest);
    CHECK(es.gap_max == ea.gap_max);
    CHECK(es.gap_mean == ea.gap_mean);
    CHECK(es.depth_max == ea.depth_max);
    CHECK(es.touching == ea.touching);
    if (g > 0.0) CHECK(es.gap_max == Approx(g).margin(1e-12));
  }
  // A round host: within its bounding box a vertex not asked for gets 0, below its distance.
  World w;
  ContactSpec pair = contact_spec_defaults();
  pair.host = add_body(w, "a", icosphere(Vec3::Zero(), 1.0, 3));
  pair.guest = add_body(w, "b", icosphere(Vec3(2.05, 0, 0), 1.0, 3));
  ReferenceMeasurer all(w, pair, cgal_only()), some(w, pair, cgal_only());
  some.needs.all = false;
  Measurement a, s;
  all.measure(w, pair, {}, a);
  some.measure(w, pair, {}, s);
  int strictly = 0, k0 = -1;
  for (std::size_t k = 0; k < a.sd_guest->size(); ++k) {
    CHECK((*s.sd_guest)[k] <= (*a.sd_guest)[k] + 1e-15);
    if ((*s.sd_guest)[k] < (*a.sd_guest)[k]) ++strictly, k0 = k0 < 0 ? static_cast<int>(k) : k0;
  }
  REQUIRE(strictly > 0);
  // That vertex touching in a reference: now exact.
  std::vector<double> touching(a.sd_guest->size(), 1.0);
  touching[static_cast<std::size_t>(k0)] = 0.0;
  ReferenceMeasurer touched(w, pair, cgal_only());
  touched.needs.all = false;
  touched.needs.touch = kTouchTolerance;
  touched.needs.ref_guest = &touching;
  Measurement t;
  touched.measure(w, pair, {}, t);
  CHECK((*t.sd_guest)[static_cast<std::size_t>(k0)] == (*a.sd_guest)[static_cast<std::size_t>(k0)]);
}

TEST_CASE("error against a reference: a hand-computed case", "[accuracy]") {
  SurfaceState ref, now;
  ref.bodies = now.bodies = {"a", "b"};
  ref.x = {{Vec3(0, 0, 0), Vec3(1, 0, 0)}, {Vec3(0, 0, 1), Vec3(1, 0, 1)}};
  ref.sd = {{0.0, 0.5}, {0.00005, 2.0}};  // a0 and b0 touch (|sd| <= 0.1 mm)
  now.x = {{Vec3(0, 0, 0.003), Vec3(1, 0, 0)}, {Vec3(0, 0.004, 1), Vec3(1, 0, 1)}};
  now.sd = {{0.002, 0.5}, {-0.001, 2.0}};
  const ReferenceErrors e = Comparison::errors(now, ref, 0, 1);
  CHECK(e.pos_err_max == Approx(0.004));
  CHECK(e.pos_err_rms == Approx(std::sqrt((0.003 * 0.003 + 0.004 * 0.004) / 4.0)));
  CHECK(e.touching == 2);
  CHECK(e.gap_max == Approx(0.002));         // a0: 0.002 - 0
  CHECK(e.gap_mean == Approx(0.001));        // b0: no gap (it penetrates)
  CHECK(e.depth_max == Approx(0.001));
  // Against itself: zero.
  const ReferenceErrors z = Comparison::errors(ref, ref, 0, 1);
  CHECK(z.pos_err_max == 0.0);
  CHECK(z.gap_max == 0.0);
}

TEST_CASE("run --compare: a run against itself gives zero, another scene is refused", "[accuracy][cli]") {
  const fs::path dir = fs::temp_directory_path() / ("harness_compare_" + std::to_string(::getpid()));
  const std::string scene = std::string(HARNESS_SOURCE_DIR) + "/experiments/scenes/cylinder_press.json";
  const std::vector<std::pair<std::string, std::string>> ov = {
      {"time.steps", "300"}, {"time.settle", "null"}, {"references.every", "100"}, {"output.frames_every", "0"},
      {"output.trajectory", "true"}};
  RunOptions opt;
  opt.measurer = make_reference_measurer;
  opt.exact_detectors = make_exact_detector;
  opt.out_dir = (dir / "a").string();
  REQUIRE(run_scene(load_scene(scene, ov), opt) == 0);
  opt.out_dir = (dir / "b").string();
  opt.compare_dir = (dir / "a").string();
  REQUIRE(run_scene(load_scene(scene, ov), opt) == 0);
  std::ifstream in(dir / "b" / "summary.json");
  const nlohmann::json s = nlohmann::json::parse(in);
  const auto& e = s["pairs"][0]["error_vs_reference"];
  CHECK(e["pos_err_max"].get<double>() == 0.0);
  CHECK(e["gap_max"].get<double>() == 0.0);
  CHECK(s["compare"]["kind"] == "run");
  // Per measured step too: the columns are zero on the measured steps.
  std::ifstream steps(dir / "b" / "steps.csv");
  auto fields = [](const std::string& line) {
    std::vector<std::string> f;
    std::string cell;
    for (char ch : line + ",") {
      if (ch == ',') f.push_back(cell), cell.clear();
      else cell += ch;
    }
    return f;
  };
  std::string line;
  std::getline(steps, line);
  const auto head = fields(line);
  const auto col = std::find(head.begin(), head.end(), "pos_err_max") - head.begin();
  REQUIRE(col < static_cast<long>(head.size()));
  int measured = 0;
  while (std::getline(steps, line)) {
    const auto f = fields(line);
    for (long c = col - 2; c <= col + 1; ++c)  // gap_max, gap_mean, pos_err_max, pos_err_rms
      if (!f[c].empty()) CHECK(std::stod(f[c]) == 0.0);
    measured += !f[col].empty();
  }
  CHECK(measured >= 3);
  // Another scene (other bodies): exit 2 naming the difference.
  opt.out_dir = (dir / "c").string();
  const std::string other = std::string(HARNESS_SOURCE_DIR) + "/experiments/scenes/sphere_collision.json";
  CHECK_THROWS_WITH(run_scene(load_scene(other, ov), opt), Catch::Contains("has no body"));
  fs::remove_all(dir);
}

TEST_CASE("a ball fired through a thin layer reads tunnelled nodes and a peak depth against a reference",
          "[accuracy][cli]") {
  // hard/fast_impact without contact: the ball (60 m/s) passes through the layer and ends below
  // it, outside: at the end no node is inside anything (depth 0), which must not read as if
  // nothing happened. Compared with a run of the same scene whose contact stops it.
  const fs::path dir = fs::temp_directory_path() / ("harness_tunnel_" + std::to_string(::getpid()));
  const std::string scene = std::string(HARNESS_SOURCE_DIR) + "/experiments/scenes/hard/fast_impact.json";
  RunOptions opt;
  opt.measurer = make_reference_measurer;
  opt.exact_detectors = make_exact_detector;
  opt.out_dir = (dir / "ref").string();
  REQUIRE(run_scene(load_scene(scene, {{"contacts.0.detector", "\"cgal\""},
                                       {"contacts.0.force", R"({"stiffness": 20000})"},
                                       {"time.guard", "\"substep\""},
                                       {"contacts.0.two_sided", "true"},
                                       {"references.every", "1"}}),
                    opt) == 0);
  opt.out_dir = (dir / "through").string();
  opt.compare_dir = (dir / "ref").string();
  REQUIRE(run_scene(load_scene(scene, {{"effects", R"(["springs", "damping", "pins", "gravity"])"},
                                       {"references.every", "1"}}),
                    opt) == 0);
  std::ifstream in(dir / "through" / "summary.json");
  const nlohmann::json s = nlohmann::json::parse(in);
  const auto& e = s["pairs"][0]["error_vs_reference"];
  INFO(e.dump());
  CHECK(e["tunnelled_guest"].get<int>() > 0);
  CHECK(e["tunnelled_peak"].get<int>() > 0);
  CHECK(e["depth_max"].get<double>() == 0.0);  // outside everything at the end ...
  CHECK(e["depth_peak"].get<double>() > 1e-3);  // ... after passing through the layer
  CHECK(e["window"]["tunnelled"]["max"].get<double>() > 0.0);
  CHECK(s["pairs"][0]["tunnelled"].get<int>() > 0);
  fs::remove_all(dir);
}

TEST_CASE("a state with some touching nodes inside and others apart reads both a gap and a depth",
          "[accuracy][cgal]") {
  // The reference: a cube resting on a layer (its bottom face at z = 0, touching). The run: the
  // cube tilted about the y axis through its bottom face's centre: the bottom face's -x half is
  // inside the layer, its +x half above it. Both figures over the same touching nodes.
  auto world_at = [](double tilt, World& w, ContactSpec& pair) {
    pair.host = add_body(w, "layer", box_surface(Vec3(-2, -2, -0.5), Vec3(3, 3, 0.0), Vec3i(10, 10, 1)));
    Surface cube = box_surface(Vec3(0, 0, 0), Vec3(1, 1, 1), Vec3i(4, 4, 4));
    const Eigen::Matrix3d R = Eigen::AngleAxisd(tilt, Vec3::UnitY()).toRotationMatrix();
    for (Vec3& p : cube.V) p = Vec3(0.5, 0.5, 0.0) + R * (p - Vec3(0.5, 0.5, 0.0));
    pair.guest = add_body(w, "cube", cube);
  };
  World w0, w1;
  ContactSpec p0, p1;
  world_at(0.0, w0, p0);
  const double tilt = 0.01;  // rad: the bottom face's edges 5 mm below and above z = 0
  world_at(tilt, w1, p1);
  ReferenceMeasurer m0(w0, p0, cgal_only()), m1(w1, p1, cgal_only());
  Measurement o0, o1;
  m0.measure(w0, p0, {}, o0);
  m1.measure(w1, p1, {}, o1);
  const SurfaceState ref = surface_state(w0, 0, 0.0, {*o0.sd_host, *o0.sd_guest});
  const SurfaceState now = surface_state(w1, 0, 0.0, {*o1.sd_host, *o1.sd_guest});
  const ReferenceErrors e = Comparison::errors(now, ref, p1.host, p1.guest);
  const double edge = 0.5 * std::sin(tilt);  // height of the bottom face's edges, m
  CHECK(e.touching >= 25);
  CHECK(e.gap_max == Approx(edge).epsilon(1e-9));    // the +x edge, above the layer
  CHECK(e.depth_max == Approx(edge).epsilon(1e-9));  // the -x edge, inside it
  CHECK(e.gap_mean > 0.0);
}

TEST_CASE("a non-finite position or signed distance is an error naming the body and node", "[accuracy]") {
  SurfaceState ref, now;
  ref.bodies = now.bodies = {"a", "b"};
  ref.x = now.x = {{Vec3(0, 0, 0), Vec3(1, 0, 0)}, {Vec3(0, 0, 1), Vec3(1, 0, 1)}};
  ref.sd = now.sd = {{0.0, 0.5}, {0.00005, 2.0}};
  CHECK_NOTHROW(Comparison::errors(now, ref, 0, 1));
  SurfaceState bad = now;
  bad.sd[1][1] = std::numeric_limits<double>::quiet_NaN();
  CHECK_THROWS_WITH(Comparison::errors(bad, ref, 0, 1), Catch::Contains("body 'b' node 1") && Catch::Contains("signed distance"));
  bad = now;
  bad.x[0][1].y() = std::numeric_limits<double>::infinity();
  CHECK_THROWS_WITH(Comparison::errors(bad, ref, 0, 1), Catch::Contains("body 'a' node 1") && Catch::Contains("position"));
  // Distances not measured at all (every one NaN): no gap or depth, positions still compared.
  bad = now;
  for (auto& v : bad.sd) std::fill(v.begin(), v.end(), std::numeric_limits<double>::quiet_NaN());
  const ReferenceErrors e = Comparison::errors(bad, ref, 0, 1);
  CHECK_FALSE(e.distances);
  CHECK(e.pos_err_max == 0.0);
}
