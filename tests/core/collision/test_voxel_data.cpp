#include "core/collision/voxel_data.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <set>

using namespace harness;

TEST_CASE("round_down_pow2 gives the largest power of two not above v", "[collision][voxel]") {
  CHECK(round_down_pow2(1.0) == 1.0);
  CHECK(round_down_pow2(0.3) == 0.25);
  CHECK(round_down_pow2(0.25) == 0.25);
  CHECK(round_down_pow2(0.2499999) == 0.125);
  CHECK(round_down_pow2(3.0) == 2.0);
  CHECK(round_down_pow2(1024.5) == 1024.0);
  const double dmin = std::numeric_limits<double>::denorm_min();
  CHECK(round_down_pow2(dmin) == dmin);
  CHECK(round_down_pow2(std::numeric_limits<double>::max()) == std::ldexp(1.0, 1023));
  for (double bad : {0.0, -1.0, std::nan(""), std::numeric_limits<double>::infinity()})
    CHECK_THROWS_AS(round_down_pow2(bad), std::invalid_argument);

  std::mt19937 rng(7);
  std::uniform_real_distribution<double> e(-40.0, 40.0);
  for (int t = 0; t < 2000; ++t) {
    const double v = std::exp2(e(rng));
    const double p = round_down_pow2(v);
    int ex = 0;
    CHECK(std::frexp(p, &ex) == 0.5);  // a power of two
    CHECK(p <= v);
    CHECK(2.0 * p > v);
  }
}

TEST_CASE("voxel_of follows the paper's index formula and rejects out-of-range points",
          "[collision][voxel]") {
  GridGeometry g;
  g.voxel = 0.5;
  g.center = Vec3(1.0, -2.0, 0.25);
  g.lo = Vec3i(-2, -1, 0);
  g.dims = Vec3i(4, 3, 2);
  Vec3i ijk;
  // A point exactly on a face belongs to the cell above it.
  CHECK(voxel_of(g, g.center, &ijk) == 2 + 4 * (1 + 3 * 0));
  CHECK(ijk == Vec3i(2, 1, 0));
  CHECK(voxel_of(g, g.center + Vec3(-1.0, -0.5, 0.0), &ijk) == 0);
  CHECK(ijk == Vec3i(0, 0, 0));
  // Upper faces of the region are outside; lower faces inside.
  CHECK(voxel_of(g, g.center + Vec3(1.0, 0.0, 0.0)) == -1);
  CHECK(voxel_of(g, g.center + Vec3(0.999, 0.0, 0.0)) >= 0);
  CHECK(voxel_of(g, g.center + Vec3(-1.0000001, 0.0, 0.0)) == -1);
  CHECK(voxel_of(g, g.center + Vec3(0.0, 0.0, -1e-12)) == -1);
  CHECK(voxel_of(g, g.center + Vec3(0.0, 0.0, 0.999)) >= 0);
  CHECK(voxel_of(g, g.center + Vec3(0.0, 0.0, 1.0)) == -1);
  const double inf = std::numeric_limits<double>::infinity();
  for (const Vec3& bad : {Vec3(1e300, 0, 0), Vec3(-1e300, 0, 0), Vec3(0, 1e19, 0), Vec3(0, 0, -3e9),
                          Vec3(inf, 0, 0), Vec3(0, -inf, 0), Vec3(0, 0, std::nan("")),
                          Vec3(std::numeric_limits<double>::max(), 0, 0)})
    CHECK(voxel_of(g, bad) == -1);
  // Round trip of linear and per-axis indices.
  for (int c = 0; c < 24; ++c) {
    const Vec3i q = voxel_ijk(g, c);
    const Vec3 p = g.center + g.voxel * (q + g.lo).cast<double>() + Vec3::Constant(0.1);
    CHECK(voxel_of(g, p) == c);
  }
  // An empty region holds nothing.
  g.dims = Vec3i(0, 3, 2);
  CHECK(voxel_of(g, g.center) == -1);
}

TEST_CASE("VoxelData fill is a counting sort that reuses its storage", "[collision][voxel]") {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  VoxelData grid;
  grid.allocate(20 * 20 * 20, 500);
  const long long cap = grid.capacity();
  for (int t = 0; t < 200; ++t) {
    GridGeometry g;
    g.voxel = 0.25 * (1 << (t % 3));
    g.center = Vec3(u(rng), u(rng), u(rng)) * 0.1;
    std::uniform_int_distribution<int> d(0, 20), l(-12, 2);
    g.dims = Vec3i(d(rng), d(rng), d(rng));
    g.lo = Vec3i(l(rng), l(rng), l(rng));
    Points x(500);
    for (auto& p : x) p = Vec3(u(rng), u(rng), u(rng));
    const int begin = t % 7, end = 500 - (t % 5);
    const long long bytes_before = grid.bytes();
    grid.fill(g, x, begin, end);
    CHECK(grid.capacity() == cap);
    CHECK(grid.bytes() == bytes_before);  // no reallocation
    // Every voxel holds exactly the nodes whose voxel it is, in increasing order.
    std::set<int> occ;
    for (int i = begin; i < end; ++i)
      if (voxel_of(g, x[i]) >= 0) occ.insert(voxel_of(g, x[i]));
    CHECK(static_cast<int>(occ.size()) == grid.occupied_count());
    int listed = 0;
    for (int i = begin; i < end; ++i) {
      const int c = voxel_of(g, x[i]);
      if (c < 0) continue;
      ++listed;
      REQUIRE(grid.occupied(c));
      CHECK(occ.count(c) == 1);
      const auto s = grid.nodes(c);
      CHECK(std::find(s.begin(), s.end(), i) != s.end());
    }
    CHECK(listed == grid.listed_nodes());
    int total = 0;
    for (long long c = 0; c < g.num_voxels(); ++c) {
      const int ci = static_cast<int>(c);
      CHECK(grid.occupied(ci) == (occ.count(ci) == 1));
      if (!grid.occupied(ci)) continue;
      const auto s = grid.nodes(ci);
      total += s.size();
      CHECK(std::is_sorted(s.begin(), s.end()));
      for (int n : s) CHECK(voxel_of(g, x[n]) == ci);
    }
    CHECK(total == listed);
    // Slots beyond this layout were cleared from the previous fill.
    for (long long c = g.num_voxels(); c < cap; ++c)
      if (grid.occupied(static_cast<int>(c))) FAIL("stale voxel " << c);
  }
  GridGeometry too_big;
  too_big.voxel = 1.0;
  too_big.dims = Vec3i(100, 100, 100);
  Points x(1, Vec3::Zero());
  CHECK_THROWS_AS(grid.fill(too_big, x, 0, 1), std::logic_error);
}
