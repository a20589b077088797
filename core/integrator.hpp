// The one position update both integrators share (symplectic Euler here, linearised backward
// Euler in implicit.hpp): a free node gets its new velocity (the integrator's rule), then
// x += h v; a pinned node is left untouched (bit-exact); a driven node moves with its
// prescribed velocity, x += h kin_v.
#pragma once

#include "core/parallel.hpp"
#include "core/world.hpp"

namespace harness {

// new_velocity(i) updates w.v[i] of free node i. Per node, independent: parallel, with the same
// result for any thread count.
template <class NewVelocity>
void update_nodes(World& w, double h, NewVelocity&& new_velocity) {
  const int n = w.num_nodes();
  const int T = threads_for(static_cast<std::size_t>(n));
  // (if: one thread never enters the OpenMP runtime, whose region costs a microsecond or so)
#pragma omp parallel for num_threads(T) if(T > 1) schedule(dynamic, 8192)
  for (int i = 0; i < n; ++i) {
    switch (w.kinematic[i]) {
      case Kinematic::free:
        new_velocity(i);
        w.x[i] += h * w.v[i];
        break;
      case Kinematic::pinned:
        break;
      case Kinematic::driven:
        w.x[i] += h * w.kin_v[i];
        break;
    }
  }
}

// Symplectic (semi-implicit) Euler: v += h f / m, then x += h v.
inline void symplectic_euler_step(World& w, double h) {
  update_nodes(w, h, [&w, h](int i) { w.v[i] += (h * w.inv_m[i]) * w.f[i]; });
}

}  // namespace harness
