// Spring and dashpot forces over the World's arrays: the hot loops of a step. Forces are the
// serial scatter's to the bit for any thread count and any instruction set (see SpringGather).
#pragma once

#include "core/world.hpp"

#include <algorithm>
#include <cstdint>
#include <vector>

namespace harness {

// Node-centric copy of the springs, built once per world: for every node its half-edges (the
// other end, the spring's index and rest length) in spring order.
//
// Why a gather: each node's force is written by one thread only, and each node sums its springs
// in spring order -- the order in which the serial scatter (f[i] += F, f[j] -= F for spring
// k = 0, 1, ...) reaches it. Every half-edge adds c * (x_other - x_self), c = tension / length
// (for a dashpot: damping times relative speed over squared length): seen from the second end
// that is exactly -F, since negation, squares and products are sign-symmetric in IEEE
// arithmetic. So the forces are bit-identical to the serial scatter, for any thread count. The
// price, evaluating each spring from both ends, is paid back by vectorising the evaluation
// (several half-edges per instruction: the SIMD kernels of core/simd, at the level core/cpu.hpp
// picks) and by threads.
//
// Which form runs (all give the same bits): with several threads, the gather; with one thread,
// the gather for linear and cubic springs when SIMD is on (vectorised, it beats the scatter) and
// the scatter itself for exponential springs and dashpots (one expm1 or division per spring:
// a gather cannot beat that on one thread), and for everything at the scalar level.
struct SpringGather {
  int nodes = -1;
  std::size_t springs = 0;
  std::vector<int> start;        // CSR over half-edges, nodes + 1
  std::vector<int> other;        // the other end of each half-edge
  std::vector<int> spring;       // its spring's index in World::springs
  std::vector<double> rest;      // its spring's rest length, m (copied: sequential reads)
  std::vector<double> stiff;     // its spring's stiffness, N/m (likewise)
  // Body of every spring at the node, or kMixedBodies (springs of several bodies meet there: a
  // hand-built world) or kNoSprings.
  static constexpr int kMixedBodies = -1, kNoSprings = -2;
  std::vector<int> node_body;
  std::vector<int> node_owner;   // body whose range holds the node, -1 none
  // Exponential law only (see spring_node_once): per spring, c from its lower end.
  std::vector<double> box;
  std::vector<std::uint8_t> is_exponential;  // per body
  bool exponential_bodies = false, mixed_nodes = false;

  bool matches(const World& w) const { return nodes == w.num_nodes() && springs == w.springs.size(); }

  void build(const World& w) {
    const Springs& s = w.springs;
    const int n = w.num_nodes();
    nodes = n;
    springs = s.size();
    start.assign(static_cast<std::size_t>(n) + 1, 0);
    for (const Edge& e : s.ends) ++start[e[0] + 1], ++start[e[1] + 1];
    for (int i = 0; i < n; ++i) start[i + 1] += start[i];
    const std::size_t H = static_cast<std::size_t>(start[n]);
    other.assign(H, 0);
    spring.assign(H, 0);
    rest.assign(H, 0.0);
    stiff.assign(H, 0.0);
    std::vector<int> cur(start.begin(), start.end() - 1);
    for (std::size_t k = 0; k < s.size(); ++k) {  // spring order: each node's list is sorted by k
      const int i = s.ends[k][0], j = s.ends[k][1];
      const int a = cur[i]++, b = cur[j]++;
      other[a] = j;
      other[b] = i;
      spring[a] = spring[b] = static_cast<int>(k);
      rest[a] = rest[b] = s.rest[k];
      stiff[a] = stiff[b] = s.k[k];
    }
    node_body.assign(static_cast<std::size_t>(n), kNoSprings);
    for (int i = 0; i < n; ++i) {
      if (start[i] == start[i + 1]) continue;
      int b = s.body[spring[start[i]]];
      for (int h = start[i] + 1; h < start[i + 1]; ++h)
        if (s.body[spring[h]] != b) b = -1;
      node_body[i] = b;
    }
    node_owner.assign(static_cast<std::size_t>(n), -1);
    for (std::size_t b = 0; b < w.bodies.size(); ++b)
      for (int i = std::max(0, w.bodies[b].begin); i < std::min(n, w.bodies[b].end); ++i)
        node_owner[i] = static_cast<int>(b);
    is_exponential.assign(w.body_law.size(), 0);
    for (std::size_t b = 0; b < w.body_law.size(); ++b)
      is_exponential[b] = w.body_law[b].kind == SpringLawKind::exponential;
    exponential_bodies = std::find(is_exponential.begin(), is_exponential.end(), 1) != is_exponential.end();
    mixed_nodes = std::find(node_body.begin(), node_body.end(), kMixedBodies) != node_body.end();
    box.assign(s.size(), 0.0);
  }

  // Node range of part t of T with about equal numbers of half-edges (only shares the work).
  void part(int T, int t, int& i0, int& i1) const {
    auto at = [&](int q) {
      if (q <= 0) return 0;
      if (q >= T) return nodes;
      const long long target = static_cast<long long>(start[nodes]) * q / T;
      return static_cast<int>(std::lower_bound(start.begin(), start.end() - 1, target) - start.begin());
    };
    i0 = at(t);
    i1 = at(t + 1);
  }
};

// Spring tensions of every spring added into f.
void add_spring_forces(const World& w, Points& f);
// Dashpots along springs (material.damping) and mass-proportional damping (material.mass_damping).
void add_damping_forces(const World& w, Points& f);
// The same with a gather kept between steps (rebuilt when the node or spring count changes).
void add_spring_forces(SpringGather& g, const World& w, Points& f);
void add_damping_forces(SpringGather& g, const World& w, Points& f);
// Elastic energy of every spring (J), the same value for any thread count.
double spring_potential(const World& w);
// Gershgorin row sums of |df/dx| of the springs (tangent stiffness k_t u u^T at the current
// strain, the compressive geometric term left out) added into rows (one per node).
void add_spring_stiffness_rows(const World& w, std::vector<Vec3>& rows);

}  // namespace harness
