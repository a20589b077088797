// The definition of the spring and dashpot forces (core/simd/kernels.hpp, SpringPassRun), one
// node and one half-edge at a time, for the tests that compare the parallel and SIMD paths
// against it: per node, its upper half-edges (to higher nodes; a spring's first end for a spring
// on one node) then its lower ones, each in spring order, into four interleaved partial sums
// (half-edge q of each list into partial q % 4), combined as (p0 + p1) + (p2 + p3).
#pragma once

#include "core/spring_forces.hpp"
#include "core/springs.hpp"
#include "core/world.hpp"

#include <cmath>
#include <vector>

namespace harness::test {

inline void reference_pass(const World& w, Points& f, bool springs, bool dashpots) {
  const Springs& S = w.springs;
  const int n = w.num_nodes();
  std::vector<std::vector<int>> up(n), lo(n);  // spring indices, in spring order
  for (std::size_t k = 0; k < S.size(); ++k) {
    const int i = S.ends[k][0], j = S.ends[k][1];
    (i <= j ? up[i] : lo[i]).push_back(static_cast<int>(k));
    (j < i ? up[j] : lo[j]).push_back(static_cast<int>(k));
  }
  for (int i = 0; i < n; ++i) {
    double el[3][4] = {}, dd[3][4] = {};
    for (const auto* list : {&up[i], &lo[i]}) {
      int q = 0;
      for (int k : *list) {
        const int j = S.ends[k][0] == i ? S.ends[k][1] : S.ends[k][0];
        const Vec3 xi = w.x[i], xj = w.x[j], vi = w.v[i], vj = w.v[j];
        const double d[3] = {xj[0] - xi[0], xj[1] - xi[1], xj[2] - xi[2]};
        const double l2 = (d[0] * d[0] + d[1] * d[1]) + d[2] * d[2];
        const int p = q++ & 3;
        if (l2 <= 0.0) continue;  // zero length: no force
        const double c = spring_force_per_length(w.body_law[S.body[k]].with(S.k[k]), S.rest[k], std::sqrt(l2));
        const double damping = w.bodies[S.body[k]].material.damping;
        const double u[3] = {vj[0] - vi[0], vj[1] - vi[1], vj[2] - vi[2]};
        const double r = 1.0 / std::sqrt(l2);
        const double s = damping * ((u[0] * d[0] + u[1] * d[1]) + u[2] * d[2]) * (r * r);
        for (int a = 0; a < 3; ++a) {
          el[a][p] += c * d[a];
          if (damping != 0.0) dd[a][p] += s * d[a];
        }
      }
    }
    for (int a = 0; a < 3; ++a) {
      if (springs) f[i][a] += (el[a][0] + el[a][1]) + (el[a][2] + el[a][3]);
      if (dashpots) f[i][a] += (dd[a][0] + dd[a][1]) + (dd[a][2] + dd[a][3]);
    }
  }
}

inline void scatter_springs(const World& w, Points& f) { reference_pass(w, f, true, false); }

inline void scatter_damping(const World& w, Points& f) {
  reference_pass(w, f, false, true);
  for (const Body& b : w.bodies)
    if (b.material.mass_damping != 0.0)
      for (int i = b.begin; i < b.end; ++i) f[i] -= (b.material.mass_damping * w.m[i]) * w.v[i];
}

}  // namespace harness::test
