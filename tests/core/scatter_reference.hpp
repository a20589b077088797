// The serial scatter the gathers replace: the definition of the spring and dashpot forces, for
// tests that compare the parallel and SIMD paths against it.
#pragma once

#include "core/spring_forces.hpp"
#include "core/world.hpp"

namespace harness::test {

inline void scatter_springs(const World& w, Points& f) {
  const Springs& s = w.springs;
  for (std::size_t k = 0; k < s.size(); ++k) {
    const int i = s.ends[k][0], j = s.ends[k][1];
    const Vec3 d = w.x[j] - w.x[i];
    const double l = d.norm();
    if (l <= 0.0) continue;
    const Vec3 fi = spring_force_per_length(w.body_law[s.body[k]].with(s.k[k]), s.rest[k], l) * d;
    f[i] += fi;
    f[j] -= fi;
  }
}

inline void scatter_damping(const World& w, Points& f) {
  const Springs& s = w.springs;
  for (std::size_t k = 0; k < s.size(); ++k) {
    const double c = w.bodies[s.body[k]].material.damping;
    if (c == 0.0) continue;
    const int i = s.ends[k][0], j = s.ends[k][1];
    const Vec3 d = w.x[j] - w.x[i];
    const double l2 = d.squaredNorm();
    if (l2 <= 0.0) continue;
    const Vec3 fi = (c * (w.v[j] - w.v[i]).dot(d) / l2) * d;
    f[i] += fi;
    f[j] -= fi;
  }
  for (const Body& b : w.bodies)
    if (b.material.mass_damping != 0.0)
      for (int i = b.begin; i < b.end; ++i) f[i] -= (b.material.mass_damping * w.m[i]) * w.v[i];
}

}  // namespace harness::test
