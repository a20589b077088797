// Instruction sets (core/cpu.hpp) and the SIMD kernels (core/simd/kernels.hpp): every level the
// processor supports, forced with set_isa, gives the scalar level's bits (and the plain
// definitions': voxel_of, the serial scatter) in every kernel. set_parallel_grain(1) makes the
// small worlds here take the parallel code paths, where the spring and dashpot gathers run.
#include "core/collision/voxel_data.hpp"
#include "core/world.hpp"
#include "core/cpu.hpp"
#include "core/parallel.hpp"
#include "core/scene/scene.hpp"
#include "core/simd/kernels.hpp"
#include "core/simulation.hpp"
#include "core/spring_forces.hpp"

#include "tests/core/scatter_reference.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

using namespace harness;
using harness::test::scatter_damping;
using harness::test::scatter_springs;

namespace {

// Restores the level, thread count and grain when a test ends (also on failure).
struct Restore {
  int t = threads();
  std::size_t g = parallel_grain();
  ~Restore() {
    reset_isa();
    set_threads(t);
    set_parallel_grain(g);
  }
};

std::vector<Isa> supported() {
  std::vector<Isa> v;
  for (Isa i : kAllIsas)
    if (isa_supported(i)) v.push_back(i);
  return v;
}

template <class T>
bool same_bits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}

bool same_bits(const Vec3& a, const Vec3& b) { return std::memcmp(a.data(), b.data(), sizeof(Vec3)) == 0; }

std::string message_of(const std::string& word) {
  try {
    parse_isa(word);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("parse_isa accepts the levels this processor runs and rejects the others", "[cpu]") {
  CHECK(isa_supported(Isa::scalar));
  for (Isa i : kAllIsas) {
    INFO(to_string(i));
    if (isa_supported(i)) {
      CHECK(parse_isa(to_string(i)) == i);
    } else {
      const std::string m = message_of(to_string(i));
      CHECK(m.rfind("HARNESS_ISA: this processor cannot run " + std::string(to_string(i)), 0) == 0);
    }
  }
  for (const char* bad : {"sse2", "AVX2", "avx-512", "", " avx", "scalar "})
    CHECK(message_of(bad) == "HARNESS_ISA: unknown instruction set '" + std::string(bad) +
                                 "' (expected scalar, avx, avx2 or avx512)");
  // A level above the processor's: rejected by name, with the ones it can run.
  CHECK_THROWS_WITH(parse_isa("avx512", "HARNESS_ISA", Isa::avx2),
                    "HARNESS_ISA: this processor cannot run avx512 (it can run scalar, avx, avx2)");
  CHECK_THROWS_WITH(parse_isa("avx", "HARNESS_ISA", Isa::scalar),
                    "HARNESS_ISA: this processor cannot run avx (it can run scalar)");
  CHECK(parse_isa("avx2", "HARNESS_ISA", Isa::avx2) == Isa::avx2);
  // The levels are cumulative: the supported ones are scalar .. cpu_isa().
  for (Isa i : kAllIsas) CHECK(isa_supported(i) == (static_cast<int>(i) <= static_cast<int>(cpu_isa())));
#if defined(__x86_64__)
  CHECK(cpu_isa() != Isa::scalar);  // every x86-64 processor this runs on has AVX, at least
#endif
}

TEST_CASE("set_isa forces a level and the kernels of that level run", "[cpu]") {
  Restore restore;
  const Isa before = isa();
  for (Isa i : supported()) {
    set_isa(i);
    CHECK(isa() == i);
    CHECK(&simd::kernels() == &simd::kernels(i));
  }
  // Each level has its own compiled kernels.
  const std::vector<Isa> s = supported();
  for (std::size_t a = 0; a < s.size(); ++a)
    for (std::size_t b = a + 1; b < s.size(); ++b)
      CHECK(simd::kernels(s[a]).voxel_cells != simd::kernels(s[b]).voxel_cells);
  for (Isa i : kAllIsas)
    if (!isa_supported(i)) CHECK_THROWS_AS(set_isa(i), std::invalid_argument);
  reset_isa();
  CHECK(isa() == before);
}

TEST_CASE("VoxelIndexer equals voxel_of at every level", "[cpu][voxel]") {
  Restore restore;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  std::uniform_int_distribution<int> d(0, 9), l(-8, 3), pick(0, 9);
  const double inf = std::numeric_limits<double>::infinity();
  for (int t = 0; t < 200; ++t) {
    GridGeometry g;
    g.voxel = 0.125 * (1 << (t % 4));
    g.center = Vec3(u(rng), u(rng), u(rng)) * 0.3;
    g.dims = Vec3i(d(rng), d(rng), d(rng));
    g.lo = Vec3i(l(rng), l(rng), l(rng));
    if (t % 50 == 7) g.lo[t % 3] = (1 << 30) - 20, g.dims[t % 3] = 19;  // at the int32 kernel's limit
    if (t % 50 == 8) g.lo[t % 3] = -(1 << 30), g.dims[t % 3] = 3;        // beyond it: the scalar operator
    Points p(static_cast<std::size_t>(t % 37));  // every remainder of 4 and 8 lanes, and none
    for (Vec3& q : p) {
      q = Vec3(u(rng), u(rng), u(rng));
      switch (pick(rng)) {  // faces of voxels, and values the range test must reject
        case 0: q[t % 3] = g.center[t % 3] + g.voxel * l(rng); break;
        case 1: q[(t + 1) % 3] = std::nan(""); break;
        case 2: q[t % 3] = (t % 2 ? 1 : -1) * inf; break;
        case 3: q[(t + 2) % 3] = (t % 2 ? 1e300 : -3e9); break;
        case 4: {  // around +-2^31 voxels from the centre: int32 conversion and wrap-around
          const double edge[] = {2147483647.0, 2147483648.0, -2147483648.0, -2147483649.0, 2147483655.5,
                                 -2147483640.0, 1073741823.5, -1073741824.5, 2251799813685248.0,
                                 -4503599627370495.5, 9.1e15};
          q[t % 3] = g.center[t % 3] + g.voxel * edge[static_cast<std::size_t>(l(rng) + 8) % 11];
          break;
        }
        case 5: q[t % 3] = g.center[t % 3] + g.voxel * (g.lo[t % 3] + g.dims[t % 3]); break;  // upper face
        case 6: {  // halves (ties of rounding to nearest), and just below a face
          const double near[] = {0.5, -0.5, 1.5, -2.5, -1e-12, -0.0, 2.5 - 1e-12};
          q[(t + 1) % 3] = g.center[(t + 1) % 3] + g.voxel * near[static_cast<std::size_t>(l(rng) + 8) % 7];
          break;
        }
        default: break;
      }
    }
    std::vector<int> want(p.size());
    for (std::size_t k = 0; k < p.size(); ++k) want[k] = voxel_of(g, p[k]);
    const VoxelIndexer idx(g);
    for (Isa i : supported()) {
      set_isa(i);
      std::vector<int> got(p.size(), -7);
      idx(p.data(), p.size(), got.data());
      INFO(to_string(i) << ", grid " << t);
      CHECK(got == want);
    }
  }
}

TEST_CASE("points_bounds and the cell range give the scalar level's bits at every level", "[cpu][voxel]") {
  Restore restore;
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  const double inf = std::numeric_limits<double>::infinity();
  for (int n : {0, 1, 3, 7, 8, 9, 17, 24, 25, 50, 3001}) {
    Points x(static_cast<std::size_t>(n) + 5);
    for (Vec3& p : x) p = Vec3(u(rng), u(rng), u(rng));
    if (n > 20) {
      x[7] = Vec3(std::nan(""), 0.0, 100.0);  // a NaN coordinate is ignored, the others count
      x[9] = Vec3(-0.0, 0.0, -inf);
      x[n / 2] = Vec3(inf, -1e300, std::nan(""));
    }
    for (int t : {1, 2, 3}) {
      set_threads(t);
      set_parallel_grain(t == 1 ? 0 : 1);
      set_isa(Isa::scalar);
      Vec3 lo0, hi0;
      points_bounds(x, 2, 2 + n, lo0, hi0);
      Vec3 blo = Vec3::Constant(inf), bhi = -blo;  // body_bounds' definition
      for (int k = 2; k < 2 + n; ++k) blo = blo.cwiseMin(x[k]), bhi = bhi.cwiseMax(x[k]);
      CHECK(lo0 == blo);
      CHECK(hi0 == bhi);
      for (Isa i : supported()) {
        set_isa(i);
        Vec3 lo, hi;
        points_bounds(x, 2, 2 + n, lo, hi);
        INFO(to_string(i) << ", " << n << " points, threads " << t);
        CHECK(same_bits(lo, lo0));
        CHECK(same_bits(hi, hi0));
      }
    }
  }

  // The cell range of a chunk: smallest voxel as unsigned (-1, outside, is the largest) and
  // largest voxel, as a plain loop.
  std::uniform_int_distribution<int> cell(-1, 1 << 20);
  for (int n : {0, 1, 4, 7, 8, 15, 16, 17, 31, 33, 4096}) {
    for (int fill = 0; fill < 3; ++fill) {
      std::vector<int> c(static_cast<std::size_t>(n));
      for (int& v : c) v = fill == 0 ? cell(rng) : fill == 1 ? -1 : (cell(rng) % 2 ? -1 : 2147483647);
      unsigned want_lo = ~0u;
      int want_hi = -1;
      for (int v : c) want_lo = std::min(want_lo, static_cast<unsigned>(v)), want_hi = std::max(want_hi, v);
      for (Isa i : supported()) {
        set_isa(i);
        unsigned lo = 5;
        int hi = 5;
        simd::kernels().cell_range(c.data(), c.size(), lo, hi);
        INFO(to_string(i) << ", " << n << " cells, fill " << fill);
        CHECK(lo == want_lo);
        CHECK(hi == want_hi);
      }
    }
  }
}

namespace {

void add_spring(World& w, int i, int j, double rest, int body) {
  w.springs.ends.push_back({i, j});
  w.springs.rest.push_back(rest);
  w.springs.k.push_back(10.0 + 5.0 * body + rest);  // per spring: a kernel mixing them up shows
  w.springs.body.push_back(body);
}

// Spring and dashpot forces at every level and thread count, against the serial scatter.
void check_forces(const World& w, const char* what) {
  Points f0(w.num_nodes(), Vec3(0.25, -1.0, 0.5)), d0 = f0;
  scatter_springs(w, f0);
  scatter_damping(w, d0);
  // The guard's rows and the springs' energy of the same pass: the scalar level's, one thread.
  set_isa(Isa::scalar);
  set_threads(1);
  std::vector<Vec3> r0(w.x.size(), Vec3(1.0, 2.0, 3.0));
  add_spring_stiffness_rows(w, r0);
  const double e0 = spring_potential(w);
  for (Isa i : supported()) {
    set_isa(i);
    for (int t : {1, 2, 3}) {
      set_threads(t);
      set_parallel_grain(t == 1 ? 0 : 1);
      Points f(w.num_nodes(), Vec3(0.25, -1.0, 0.5)), d = f;
      add_spring_forces(w, f);
      add_damping_forces(w, d);
      std::vector<Vec3> r(w.x.size(), Vec3(1.0, 2.0, 3.0));
      add_spring_stiffness_rows(w, r);
      const double e = spring_potential(w);
      INFO(what << ": " << to_string(i) << ", threads " << t);
      CHECK(same_bits(f, f0));
      CHECK(same_bits(d, d0));
      CHECK(std::memcmp(r.data(), r0.data(), r.size() * sizeof(Vec3)) == 0);
      CHECK(std::memcmp(&e, &e0, sizeof e) == 0);
    }
  }
}

}  // namespace

TEST_CASE("spring and damping forces give the serial scatter's bits at every level", "[cpu][springs]") {
  Restore restore;
  // One body per law, each with dashpots; the sphere's nodes have many springs.
  const std::string text = R"({"name":"laws","time":{"dt":1e-5,"steps":0},"effects":["springs"],
    "bodies":[{"name":"lin","shape":{"type":"box","min":[0,0,0],"max":[0.02,0.01,0.01],"cells":[4,2,2]},
               "material":{"stiffness":40,"law":"linear","damping":0.01}},
              {"name":"cub","shape":{"type":"box","min":[0,0,0.02],"max":[0.02,0.01,0.03],"cells":[3,2,2]},
               "material":{"stiffness":70,"law":"cubic","nonlinearity":4,"damping":0.004}},
              {"name":"exp","shape":{"type":"sphere","center":[0,0,0.05],"radius":0.01,"subdivisions":1,
               "fill":"volume"},
               "material":{"stiffness":20,"law":"exponential","nonlinearity":3,"damping":0.02}}]})";
  Simulation sim(parse_scene(text, "laws.json"));
  World& w = sim.world();
  w.bodies[2].material.mass_damping = 3.0;
  w.bodies[0].material.mass_damping = 0.5;
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> u(-0.003, 0.003);
  for (int i = 0; i < w.num_nodes(); ++i) {
    w.x[i] += Vec3(u(rng), u(rng), u(rng));
    w.v[i] = Vec3(u(rng), u(rng), u(rng)) * 100.0;
  }
  const Body lin = w.bodies[0], cub = w.bodies[1], ex = w.bodies[2];
  // Hubs with more half-edges than a kernel chunk (64): springs from the first node of the
  // linear and the cubic box to every other node of its body, three times over.
  for (int rep = 0; rep < 3; ++rep)
    for (const Body* b : {&lin, &cub})
      for (int j = b->begin + 1; j < b->end; ++j) add_spring(w, b->begin, j, 0.004 + 0.001 * rep, b == &lin ? 0 : 1);
  // Zero-length springs: coincident ends (no force, no dashpot) in both polynomial laws.
  w.x[lin.begin + 6] = w.x[lin.begin + 5];
  add_spring(w, lin.begin + 5, lin.begin + 6, 0.003, 0);
  w.x[cub.begin + 3] = w.x[cub.begin + 2];
  add_spring(w, cub.begin + 2, cub.begin + 3, 0.002, 1);
  check_forces(w, "one law per node");

  // Nodes where springs of two bodies meet (law and damping per spring): a linear spring into
  // the cubic box, an exponential one from the sphere into the cubic box.
  add_spring(w, lin.begin + 1, cub.begin + 2, 0.015, 0);
  add_spring(w, ex.begin, cub.end - 1, 0.04, 2);
  check_forces(w, "mixed nodes");
}

TEST_CASE("the bundled scenes' state hashes are the same at every level", "[cpu][determinism]") {
  // (tests/cli/test_golden.sh checks the full runs against the golden hashes at every level.)
  Restore restore;
  for (const char* name : {"cylinder_press", "implant_expansion", "sphere_collision"}) {
    const Scene scene = load_scene(std::string(HARNESS_SOURCE_DIR) + "/experiments/scenes/" + name + ".json",
                                   {{"references.solvers", "[]"}, {"contacts.0.detector", "\"voxel\""}});
    auto hash = [&] {
      Simulation sim(scene);
      for (int s = 0; s < 30; ++s) sim.step();
      return state_hash(sim.world());
    };
    set_isa(Isa::scalar);
    set_threads(1);
    set_parallel_grain(0);
    const std::string h0 = hash();
    for (Isa i : supported()) {
      set_isa(i);
      for (int t : {1, 2}) {
        set_threads(t);
        set_parallel_grain(t == 1 ? 0 : 1);
        INFO(name << ": " << to_string(i) << ", threads " << t);
        CHECK(hash() == h0);
      }
    }
  }
}

TEST_CASE("the arithmetic floor kernel sums 1 / sqrt at every level", "[cpu]") {
  Restore restore;
  // 4^-k for k = 0..36 (1 / sqrt = 2^k, exact) and a tail that is not a multiple of any width.
  std::vector<double> a;
  double want = 0.0;
  for (int k = 0; k <= 36; ++k) a.push_back(std::ldexp(1.0, -2 * k)), want += std::ldexp(1.0, k);
  for (Isa i : supported()) {
    INFO(to_string(i));
    const double got = simd::kernels(i).sqrt_div(a.data(), a.size());
    CHECK(got == want);  // every term and partial sum is an integer below 2^53: exact
    CHECK(simd::kernels(i).sqrt_div(a.data(), 0) == 0.0);
    CHECK(simd::kernels(i).sqrt_div(a.data() + 1, 3) == 2.0 + 4.0 + 8.0);
  }
}

TEST_CASE("the force pass's floor kernel sums the reciprocal lengths at every level", "[cpu]") {
  Restore restore;
  // Springs of lengths 2^-k along the axes (1 / l = 2^k exact); n not a multiple of any width.
  std::vector<double> x = {0.0, 0.0, 0.0};
  std::vector<int> self, other;
  double want = 0.0;
  for (int k = 0; k <= 21; ++k) {
    const int a = k % 3;
    double p[3] = {0.0, 0.0, 0.0};
    p[a] = (k % 2 ? -1.0 : 1.0) * std::ldexp(1.0, -k);
    const int node = static_cast<int>(x.size() / 3);
    x.insert(x.end(), p, p + 3);
    self.push_back(k % 2 ? node : 0), other.push_back(k % 2 ? 0 : node);
    want += std::ldexp(1.0, k);
  }
  for (Isa i : supported()) {
    INFO(to_string(i));
    CHECK(simd::kernels(i).pass_floor(x.data(), self.data(), other.data(), self.size()) == want);
    CHECK(simd::kernels(i).pass_floor(x.data(), self.data(), other.data(), 0) == 0.0);
    CHECK(simd::kernels(i).pass_floor(x.data(), self.data() + 1, other.data() + 1, 2) == 2.0 + 4.0);
  }
}
