// Parallel kernels (core/parallel.hpp): results never depend on the thread count, and the
// fast forms equal their plain serial definitions bit for bit. set_parallel_grain(1) makes the
// small worlds here take the parallel code paths.
#include "core/collision/voxel_data.hpp"
#include "core/world.hpp"
#include "core/spring_forces.hpp"
#include "core/parallel.hpp"
#include "core/scene/scene.hpp"
#include "core/simulation.hpp"

#include "tests/core/scatter_reference.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <string>

using namespace harness;
using harness::test::scatter_damping;
using harness::test::scatter_springs;

namespace {

// Restores the thread count and grain when a test ends (also on failure).
struct ThreadsGuard {
  int t = threads();
  std::size_t g = parallel_grain();
  ~ThreadsGuard() {
    set_threads(t);
    set_parallel_grain(g);
  }
};

bool same_bits(const Points& a, const Points& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(Vec3)) == 0;
}

std::string bundled(const std::string& name) {
  return std::string(HARNESS_SOURCE_DIR) + "/experiments/scenes/" + name + ".json";
}

std::string run_hash(const Scene& scene, int steps, std::vector<int>* contacts = nullptr,
                     SimulationOptions::Overlap overlap = SimulationOptions::Overlap::automatic) {
  SimulationOptions so;
  so.overlap = overlap;
  Simulation sim(scene, so);
  for (int s = 0; s < steps; ++s) {
    sim.step();
    if (contacts)
      for (const Pair& p : sim.pairs()) contacts->push_back(p.last.contacts);
  }
  return state_hash(sim.world());
}

}  // namespace

TEST_CASE("a run's state hash is the same with 1 and 2 threads", "[parallel][determinism]") {
  ThreadsGuard guard;
  for (const char* name : {"cylinder_press", "implant_expansion", "sphere_collision"}) {
    // References off (they only measure); gravity and mass damping on, to cover those kernels.
    const Scene scene = load_scene(bundled(name), {{"references.solvers", "[]"}, {"contacts.0.detector", "\"voxel\""}});
    std::vector<std::string> hashes;
    std::vector<std::vector<int>> contacts;
    for (int t : {1, 2, 3}) {
      set_threads(t);
      set_parallel_grain(t == 1 ? 0 : 1);
      contacts.emplace_back();
      hashes.push_back(run_hash(scene, 40, &contacts.back()));
    }
    INFO(name);
    CHECK(hashes[0] == hashes[1]);
    CHECK(hashes[0] == hashes[2]);
    CHECK(contacts[0] == contacts[1]);
    CHECK(contacts[0] == contacts[2]);
  }
  // Every force kernel at once: springs, damping (dashpots and mass damping), gravity.
  const std::string text = R"({"name":"all","time":{"dt":2e-5,"steps":0},
    "effects":["springs","damping","gravity","pins","contact"],
    "bodies":[{"name":"a","shape":{"type":"box","min":[0,0,0],"max":[0.04,0.04,0.01],"cells":[8,8,2]},
               "material":{"stiffness":60,"law":"exponential","nonlinearity":3,"damping":0.003},
               "pins":[{"side":"-z"}]},
              {"name":"b","shape":{"type":"sphere","center":[0.02,0.02,0.017],"radius":0.008,
               "subdivisions":2,"fill":"volume"},
               "material":{"stiffness":90,"law":"cubic","nonlinearity":2,"damping":0.002}}],
    "contacts":[{"host":"a","guest":"b","voxel_size":0.002,"force":"auto"}]})";
  Scene scene = parse_scene(text, "all.json");
  scene.bodies[1].material.mass_damping = 5.0;  // not a scene key; exercised here directly
  set_threads(1);
  set_parallel_grain(0);
  const std::string h1 = run_hash(scene, 60);
  set_threads(2);
  set_parallel_grain(1);
  CHECK(run_hash(scene, 60) == h1);
}

TEST_CASE("detection overlapping the springs' pass gives one thread's state and contacts", "[parallel][determinism]") {
  ThreadsGuard guard;
  for (const char* name : {"cylinder_press", "implant_expansion", "sphere_collision"}) {
    const Scene scene = load_scene(bundled(name), {{"references.solvers", "[]"}, {"contacts.0.detector", "\"voxel\""}});
    set_threads(1);
    set_parallel_grain(0);
    std::vector<int> c1, c2, c3;
    const std::string h1 = run_hash(scene, 40, &c1);
    set_parallel_grain(1);
    for (int t : {2, 3}) {
      set_threads(t);
      std::vector<int>& c = t == 2 ? c2 : c3;
      INFO(name << ", threads " << t);
      CHECK(run_hash(scene, 40, &c, SimulationOptions::Overlap::always) == h1);
      CHECK(c == c1);
    }
  }
}

TEST_CASE("spring and damping gathers equal the serial scatter bit for bit", "[parallel][springs]") {
  ThreadsGuard guard;
  const std::string text = R"({"name":"laws","time":{"dt":1e-5,"steps":0},"effects":["springs"],
    "bodies":[{"name":"lin","shape":{"type":"box","min":[0,0,0],"max":[0.02,0.01,0.01],"cells":[4,2,2]},
               "material":{"stiffness":40,"law":"linear","damping":0.01}},
              {"name":"cub","shape":{"type":"box","min":[0,0,0.02],"max":[0.02,0.01,0.03],"cells":[3,2,2]},
               "material":{"stiffness":70,"law":"cubic","nonlinearity":4,"damping":0}},
              {"name":"exp","shape":{"type":"sphere","center":[0,0,0.05],"radius":0.01,"subdivisions":1,
               "fill":"volume"},
               "material":{"stiffness":20,"law":"exponential","nonlinearity":3,"damping":0.02}}]})";
  Simulation sim(parse_scene(text, "laws.json"));
  World& w = sim.world();
  w.bodies[2].material.mass_damping = 3.0;
  // A spring owned by body 0 reaching into body 1: nodes where laws of two bodies meet.
  w.springs.ends.push_back({w.bodies[0].begin + 1, w.bodies[1].begin + 2});
  w.springs.rest.push_back(0.015);
  w.springs.k.push_back(50.0);
  w.springs.body.push_back(0);
  // And an exponential spring from the sphere into the cubic box (mailbox of spring_node_once).
  w.springs.ends.push_back({w.bodies[2].begin, w.bodies[1].end - 1});  // adjacent: same thread
  w.springs.rest.push_back(0.04);
  w.springs.k.push_back(20.0);
  w.springs.body.push_back(2);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-0.003, 0.003);
  for (int i = 0; i < w.num_nodes(); ++i) {
    w.x[i] += Vec3(u(rng), u(rng), u(rng));
    w.v[i] = Vec3(u(rng), u(rng), u(rng)) * 100.0;
  }
  w.x[w.bodies[0].begin + 5] = w.x[w.bodies[0].begin + 6];  // coincident ends: no force
  Points f0(w.num_nodes(), Vec3(0.25, -1.0, 0.5)), d0 = f0;
  scatter_springs(w, f0);
  scatter_damping(w, d0);
  for (int t : {1, 2, 3}) {
    set_threads(t);
    set_parallel_grain(t == 1 ? 0 : 1);
    Points f(w.num_nodes(), Vec3(0.25, -1.0, 0.5)), d = f;
    add_spring_forces(w, f);
    add_damping_forces(w, d);
    INFO("threads " << t);
    CHECK(same_bits(f, f0));
    CHECK(same_bits(d, d0));
  }
  // The spring potential does not depend on the thread count either.
  set_threads(1);
  set_parallel_grain(0);
  const double e1 = spring_potential(w);
  set_threads(2);
  set_parallel_grain(1);
  CHECK(spring_potential(w) == e1);
}

TEST_CASE("VoxelIndexer (scalar and batch) equals voxel_of", "[parallel][voxel]") {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  std::uniform_int_distribution<int> d(0, 9), l(-8, 3), pick(0, 9);
  const double inf = std::numeric_limits<double>::infinity();
  for (int t = 0; t < 300; ++t) {
    GridGeometry g;
    g.voxel = 0.125 * (1 << (t % 4));
    g.center = Vec3(u(rng), u(rng), u(rng)) * 0.3;
    g.dims = Vec3i(d(rng), d(rng), d(rng));
    g.lo = Vec3i(l(rng), l(rng), l(rng));
    Points p(4 * 37 + t % 4);
    for (Vec3& q : p) {
      q = Vec3(u(rng), u(rng), u(rng));
      switch (pick(rng)) {  // faces of voxels, and values the range test must reject
        case 0: q[t % 3] = g.center[t % 3] + g.voxel * l(rng); break;
        case 1: q[(t + 1) % 3] = std::nan(""); break;
        case 2: q[t % 3] = (t % 2 ? 1 : -1) * inf; break;
        case 3: q[(t + 2) % 3] = (t % 2 ? 1e300 : -3e9); break;
        case 4: {  // around +-2^31 voxels from the centre: int32 conversion and wrap-around
          const double edge[] = {2147483647.0, 2147483648.0, -2147483648.0, -2147483649.0, 2147483655.5, -2147483640.0};
          q[t % 3] = g.center[t % 3] + g.voxel * edge[static_cast<std::size_t>(l(rng) + 8) % 6];
          break;
        }
        default: break;
      }
    }
    const VoxelIndexer idx(g);
    std::vector<int> batch(p.size(), -7);
    idx(p.data(), p.size(), batch.data());
    for (std::size_t k = 0; k < p.size(); ++k) {
      const int want = voxel_of(g, p[k]);
      INFO("point " << k << ": " << p[k].transpose());
      CHECK(idx(p[k]) == want);
      CHECK(batch[k] == want);
    }
  }
}

TEST_CASE("points_bounds equals body_bounds; parallel fill lists the same nodes", "[parallel][voxel]") {
  ThreadsGuard guard;
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  Points x(3001);
  for (Vec3& p : x) p = Vec3(u(rng), u(rng), u(rng));
  x[17] = Vec3(std::nan(""), 0.0, 100.0);  // a NaN coordinate is ignored, the others count
  for (int t : {1, 2, 3}) {
    set_threads(t);
    set_parallel_grain(t == 1 ? 0 : 1);
    Vec3 lo, hi;
    points_bounds(x, 3, 2999, lo, hi);
    Vec3 blo = Vec3::Constant(std::numeric_limits<double>::infinity()), bhi = -blo;
    for (int i = 3; i < 2999; ++i) {
      blo = blo.cwiseMin(x[i]);
      bhi = bhi.cwiseMax(x[i]);
    }
    CHECK(lo == blo);
    CHECK(hi == bhi);
  }

  for (const Vec3i& dims : {Vec3i(14, 15, 10), Vec3i(2, 2, 3)}) {  // sparse, and every voxel full
    GridGeometry g;
    g.voxel = dims.x() == 2 ? 2.0 : 0.25;
    g.center = Vec3(0.1, -0.05, 0.02);
    g.lo = -dims / 2;
    g.dims = dims;
    VoxelData one, many;
    set_threads(1);
    set_parallel_grain(0);
    one.allocate(g.num_voxels(), 3000);
    one.fill(g, x, 1, 3001);
    for (int t : {2, 3, 5}) {
      set_threads(t);
      set_parallel_grain(1);
      many.allocate(g.num_voxels(), 3000);
      for (int rep = 0; rep < 2; ++rep) {  // the second fill reuses the storage
        many.fill(g, x, 1, 3001);
        CHECK(many.listed_nodes() == one.listed_nodes());
        CHECK(many.occupied_count() == one.occupied_count());
        for (int c = 0; c < g.num_voxels(); ++c) {
          const auto a = one.nodes(c), b = many.nodes(c);
          REQUIRE(std::vector<int>(a.begin(), a.end()) == std::vector<int>(b.begin(), b.end()));
        }
      }
    }
  }
}
