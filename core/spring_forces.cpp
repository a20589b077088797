#include "core/spring_forces.hpp"

#include "core/cpu.hpp"
#include "core/parallel.hpp"
#include "core/simd/kernels.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace harness {
namespace {

static_assert(sizeof(Vec3) == 3 * sizeof(double), "the kernels take points as three packed doubles");

// The law of a body, chosen at compile time (springs.hpp: the expressions every path shares).
template <SpringLawKind K>
inline double per_length_of(const SpringLaw& law, double L0, double l) {  // law: one spring's
  if constexpr (K == SpringLawKind::linear) return linear_per_length(law, L0, l);
  if constexpr (K == SpringLawKind::cubic) return cubic_per_length(law, L0, l);
  if constexpr (K == SpringLawKind::exponential) {
    const double x = exponential_arg(law, L0, l);
    return exponential_per_length(law, L0, l, x, spring_expm1(x));
  }
}

// Node i's spring force added to acc, one half-edge after the other in spring order (a
// half-edge of zero length adds nothing: the scatter's `if (l <= 0) continue`), evaluating each
// spring once, for laws whose evaluation dwarfs the rest (the exponential: one expm1 per
// spring). The lower end of a spring whose ends both lie in this thread's node range [i0, i1)
// leaves c in the spring's mailbox slot, and the higher end, which comes later in the same
// thread, reads it; other springs are evaluated at both ends. c is the same number either way,
// so the thread count still changes nothing.
template <SpringLawKind K>
void spring_node_once(const SpringGather& g, const BodyLaw& law, const Points& x, int i, int i0, int i1,
                      double* box, Vec3& acc) {
  const Vec3 xi = x[i];
  for (int h = g.start[i]; h < g.start[i + 1]; ++h) {
    const int j = g.other[h];
    const Vec3 d = x[j] - xi;
    double c;
    if (j < i && j >= i0) {
      if (d.squaredNorm() <= 0.0) continue;  // sqrt(l2) <= 0 exactly when l2 <= 0
      c = box[g.spring[h]];
    } else {
      const double l = d.norm();
      if (l <= 0.0) continue;
      c = per_length_of<K>(law.with(g.stiff[h]), g.rest[h], l);
      if (j > i && j < i1) box[g.spring[h]] = c;
    }
    acc += c * d;
  }
}

// The serial scatter itself (f[i] += F, f[j] -= F in spring order), for the springs of the
// bodies `only` selects (all when null): with one thread it is the fastest form for the
// exponential law, whose expm1 costs more than anything a gather saves.
template <SpringLawKind K>
void scatter_run(const World& w, const BodyLaw& law, std::size_t k0, std::size_t k1, Points& f) {
  const Springs& s = w.springs;
  for (std::size_t k = k0; k < k1; ++k) {
    const int i = s.ends[k][0], j = s.ends[k][1];
    const Vec3 d = w.x[j] - w.x[i];
    const double l = d.norm();
    if (l <= 0.0) continue;  // coincident ends: no defined direction, no force
    const Vec3 fi = per_length_of<K>(law.with(s.k[k]), s.rest[k], l) * d;  // pulls i toward j
    f[i] += fi;
    f[j] -= fi;
  }
}

// The exponential law in blocks: the expm1 of a block at once (spring_expm1_batch, the same bits
// as one at a time), then per_length_of's remaining operations and the scatter in spring order.
template <>
void scatter_run<SpringLawKind::exponential>(const World& w, const BodyLaw& law, std::size_t k0, std::size_t k1,
                                             Points& f) {
  const Springs& s = w.springs;
  constexpr int B = 64;
  double X[B], E[B], Lr[B];
  Vec3 D[B];
  for (std::size_t b = k0; b < k1; b += B) {
    const int m = static_cast<int>(std::min<std::size_t>(B, k1 - b));
    for (int q = 0; q < m; ++q) {
      const std::size_t k = b + static_cast<std::size_t>(q);
      D[q] = w.x[s.ends[k][1]] - w.x[s.ends[k][0]];
      Lr[q] = D[q].norm();
      X[q] = exponential_arg(law.with(s.k[k]), s.rest[k], Lr[q]);
    }
    spring_expm1_batch(X, E, m);
    for (int q = 0; q < m; ++q) {
      const double l = Lr[q];
      if (l <= 0.0) continue;
      const std::size_t k = b + static_cast<std::size_t>(q);
      const double c = exponential_per_length(law.with(s.k[k]), s.rest[k], l, X[q], E[q]);
      const Vec3 fi = c * D[q];
      f[s.ends[k][0]] += fi;
      f[s.ends[k][1]] -= fi;
    }
  }
}

void scatter_spring_forces(const World& w, Points& f, const std::vector<std::uint8_t>* only) {
  // Runs of consecutive springs of one body, each with its law inlined; spring order kept.
  const Springs& s = w.springs;
  const std::size_t n = s.size();
  for (std::size_t k0 = 0, k1; k0 < n; k0 = k1) {
    const int b = s.body[k0];
    for (k1 = k0 + 1; k1 < n && s.body[k1] == b;) ++k1;
    if (only && !(*only)[b]) continue;
    const BodyLaw& law = w.body_law[b];
    switch (law.kind) {
      case SpringLawKind::linear: scatter_run<SpringLawKind::linear>(w, law, k0, k1, f); break;
      case SpringLawKind::cubic: scatter_run<SpringLawKind::cubic>(w, law, k0, k1, f); break;
      case SpringLawKind::exponential: scatter_run<SpringLawKind::exponential>(w, law, k0, k1, f); break;
    }
  }
}

void scatter_damping_forces(const World& w, Points& f) {
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
  for (const Body& b : w.bodies) {
    const double a = b.material.mass_damping;
    if (a == 0.0) continue;
    for (int i = b.begin; i < b.end; ++i) f[i] -= (a * w.m[i]) * w.v[i];
  }
}

// The kernels' view of a Points array: three doubles per node (null when empty).
const double* coords(const Points& p) { return p.empty() ? nullptr : p[0].data(); }
double* coords(Points& p) { return p.empty() ? nullptr : p[0].data(); }

void gather_spring_forces(SpringGather& g, const World& w, Points& f) {
  const int T = threads_for(static_cast<std::size_t>(g.start[g.nodes]), 32768);
  const Isa level = isa();
  const simd::Kernels& kern = simd::kernels(level);
  double* box = g.box.data();
  // One thread: exponential bodies by the scatter, the others by the (vectorised) gather. Both
  // give the scatter's bits, and no node has springs of both kinds unless some node is mixed.
  // (Without SIMD the gather has nothing to repay its double evaluation on one thread.)
  bool scatter_exp = false;
  if (T == 1) {
    if (level == Isa::scalar || g.mixed_nodes) return scatter_spring_forces(w, f, nullptr);
    if (g.exponential_bodies) {
      scatter_spring_forces(w, f, &g.is_exponential);
      scatter_exp = true;
    }
  }
  const simd::SpringRun all{g.start.data(), g.other.data(), g.rest.data(), g.stiff.data(), coords(w.x), coords(f), 0.0, 0, 0};
  // Parts handed out dynamically, several per thread: a thread that the system deschedules
  // (the machine is shared) delays one small part, not half the work. The parts only share the
  // work: the forces are the same for any partition.
  const int P = T == 1 ? 1 : 4 * T;
#pragma omp parallel for num_threads(T) schedule(dynamic, 1)
  for (int t = 0; t < P; ++t) {
    int i0, i1;
    g.part(P, t, i0, i1);
    for (int i = i0; i < i1; ++i) {
      const int b = g.node_body[i];
      if (b == SpringGather::kNoSprings) continue;
      if (scatter_exp && b >= 0 && g.is_exponential[b]) continue;
      if (b >= 0 && w.body_law[b].kind != SpringLawKind::exponential) {
        // The run of nodes of this body (a linear or cubic law) from i on: the SIMD kernel.
        const BodyLaw& law = w.body_law[b];
        int e = i + 1;
        while (e < i1 && g.node_body[e] == b) ++e;
        simd::SpringRun run = all;
        run.beta = law.beta, run.i0 = i, run.i1 = e;
        (law.kind == SpringLawKind::linear ? kern.springs_linear : kern.springs_cubic)(run);
        i = e - 1;
        continue;
      }
      Vec3 acc = f[i];
      if (b >= 0) {
        spring_node_once<SpringLawKind::exponential>(g, w.body_law[b], w.x, i, i0, i1, box, acc);
      } else {  // springs of several bodies meet here (hand-built worlds): the law per spring
        const Vec3 xi = w.x[i];
        for (int h = g.start[i]; h < g.start[i + 1]; ++h) {
          const int j = g.other[h];
          const Vec3 d = w.x[j] - xi;
          const double l = d.norm();
          if (l <= 0.0) continue;
          const double c = spring_force_per_length(w.body_law[w.springs.body[g.spring[h]]].with(g.stiff[h]), g.rest[h], l);
          if (j > i && j < i1) box[g.spring[h]] = c;  // for a higher end using spring_node_once
          acc += c * d;
        }
      }
      f[i] = acc;
    }
  }
}

void gather_damping_forces(const SpringGather& g, const World& w, Points& f) {
  const int T = threads_for(static_cast<std::size_t>(g.start[g.nodes]), 32768);
  if (T == 1) return scatter_damping_forces(w, f);  // the same bits; faster on one thread
  const simd::Kernels& kern = simd::kernels();
  const simd::DashpotRun all{g.start.data(), g.other.data(), coords(w.x), coords(w.v), coords(f), 0.0, 0, 0};
  // Mass-proportional damping of node i, after every dashpot, as in the serial order.
  auto mass_damping = [&](int i, Vec3& acc) {
    const int owner = g.node_owner[i];
    const double a = owner >= 0 ? w.bodies[owner].material.mass_damping : 0.0;
    if (a != 0.0) acc -= (a * w.m[i]) * w.v[i];
  };
  const int P = T == 1 ? 1 : 4 * T;  // dynamic parts, as for the springs
#pragma omp parallel for num_threads(T) schedule(dynamic, 1)
  for (int t = 0; t < P; ++t) {
    int i0, i1;
    g.part(P, t, i0, i1);
    for (int i = i0; i < i1; ++i) {
      const int nb = g.node_body[i];
      if (nb >= 0 && w.bodies[nb].material.damping != 0.0) {
        // The run of nodes of this body from i on: its dashpots by the SIMD kernel.
        int e = i + 1;
        while (e < i1 && g.node_body[e] == nb) ++e;
        simd::DashpotRun run = all;
        run.c = w.bodies[nb].material.damping, run.i0 = i, run.i1 = e;
        kern.dashpots(run);
        for (; i < e; ++i) mass_damping(i, f[i]);
        --i;
        continue;
      }
      Vec3 acc = f[i];
      if (nb == -1) {  // springs of several bodies meet here: the damping per spring
        const Vec3 xi = w.x[i], vi = w.v[i];
        for (int h = g.start[i]; h < g.start[i + 1]; ++h) {
          const double c = w.bodies[w.springs.body[g.spring[h]]].material.damping;
          if (c == 0.0) continue;
          const int j = g.other[h];
          const Vec3 d = w.x[j] - xi;
          const double l2 = d.squaredNorm();
          if (l2 <= 0.0) continue;
          acc += (c * (w.v[j] - vi).dot(d) / l2) * d;  // as the scatter: exactly -F at the other end
        }
      }
      mass_damping(i, acc);
      f[i] = acc;
    }
  }
}

}  // namespace

void add_spring_forces(SpringGather& g, const World& w, Points& f) {
  if (!g.matches(w)) g.build(w);
  gather_spring_forces(g, w, f);
}

void add_spring_forces(const World& w, Points& f) {
  SpringGather g;
  add_spring_forces(g, w, f);
}

double spring_potential(const World& w) {
  // Fixed chunks of springs, summed in chunk order: the same value for any thread count.
  const Springs& s = w.springs;
  constexpr std::size_t kChunk = 65536;
  const std::size_t n = s.size(), chunks = (n + kChunk - 1) / kChunk;
  std::vector<double> part(chunks, 0.0);
  const int T = threads_for(n, 65536);
#pragma omp parallel for num_threads(T) schedule(static)
  for (std::size_t c = 0; c < chunks; ++c) {
    double e = 0.0;
    for (std::size_t k = c * kChunk; k < std::min(n, (c + 1) * kChunk); ++k) {
      const double l = (w.x[s.ends[k][1]] - w.x[s.ends[k][0]]).norm();
      e += spring_energy(w.body_law[s.body[k]].with(s.k[k]), s.rest[k], l);
    }
    part[c] = e;
  }
  double e = 0.0;
  for (double p : part) e += p;
  return e;
}

void add_damping_forces(SpringGather& g, const World& w, Points& f) {
  if (!g.matches(w)) g.build(w);
  gather_damping_forces(g, w, f);
}

void add_damping_forces(const World& w, Points& f) {
  SpringGather g;
  add_damping_forces(g, w, f);
}

namespace {

// |df/dl| / l^2 of law K at length l = sqrt(l2) (spring_tangent over the squared length, in as
// few divisions as each law allows; the linear law needs no length). The exponential law has
// its own gershgorin_run, which takes its exps in blocks.
template <SpringLawKind K>
inline double tangent_over_l2(const SpringLaw& law, double L0, double l2) {
  static_assert(K != SpringLawKind::exponential, "gershgorin_run<exponential> handles it");
  if constexpr (K == SpringLawKind::linear) return std::fabs(law.k) / l2;
  const double s = std::sqrt(l2) - L0, L2 = L0 * L0;
  return std::fabs(law.k * (L2 + 3.0 * law.beta * s * s)) / (L2 * l2);
}

// Row sums of the springs [k0, k1), all of one law: the block k u u^T, u = d / l, adds
// 2 k |u_a| |u|_1 = 2 (k / l^2) |d_a| |d|_1 to row a of both ends.
template <SpringLawKind K>
void gershgorin_run(const World& w, const BodyLaw& law, std::size_t k0, std::size_t k1, std::vector<Vec3>& rows) {
  const Springs& s = w.springs;
  for (std::size_t k = k0; k < k1; ++k) {
    const int i = s.ends[k][0], j = s.ends[k][1];
    const Vec3 d = w.x[j] - w.x[i];
    const double l2 = d.squaredNorm();
    if (!(l2 > 0.0)) continue;
    const Vec3 a = d.cwiseAbs();
    const Vec3 r = (2.0 * tangent_over_l2<K>(law.with(s.k[k]), s.rest[k], l2) * a.sum()) * a;
    rows[i] += r;
    rows[j] += r;
  }
}

// The exponential law in blocks, its exp for a block at once (spring_exp_batch).
template <>
void gershgorin_run<SpringLawKind::exponential>(const World& w, const BodyLaw& law, std::size_t k0,
                                                std::size_t k1, std::vector<Vec3>& rows) {
  const Springs& s = w.springs;
  constexpr int B = 64;
  double X[B], E[B], L2[B];
  for (std::size_t b = k0; b < k1; b += B) {
    const int m = static_cast<int>(std::min<std::size_t>(B, k1 - b));
    for (int q = 0; q < m; ++q) {
      const std::size_t k = b + static_cast<std::size_t>(q);
      const Vec3 d = w.x[s.ends[k][1]] - w.x[s.ends[k][0]];
      L2[q] = d.squaredNorm();
      const double L0 = s.rest[k];
      X[q] = L2[q] > 0.0 ? exponential_arg(law.with(s.k[k]), L0, std::sqrt(L2[q])) : 0.0;
    }
    spring_exp_batch(X, E, m);
    for (int q = 0; q < m; ++q) {
      if (!(L2[q] > 0.0)) continue;
      const std::size_t k = b + static_cast<std::size_t>(q);
      const int i = s.ends[k][0], j = s.ends[k][1];
      const Vec3 a = (w.x[j] - w.x[i]).cwiseAbs();
      const Vec3 r = (2.0 * (std::fabs(s.k[k] * E[q]) / L2[q]) * a.sum()) * a;
      rows[i] += r;
      rows[j] += r;
    }
  }
}

}  // namespace

void add_spring_stiffness_rows(const World& w, std::vector<Vec3>& rows) {
  const Springs& s = w.springs;
  const std::size_t ns = s.size();
  for (std::size_t k0 = 0, k1; k0 < ns; k0 = k1) {  // runs of springs of one body
    const int b = s.body[k0];
    for (k1 = k0 + 1; k1 < ns && s.body[k1] == b;) ++k1;
    const BodyLaw& law = w.body_law[b];
    switch (law.kind) {
      case SpringLawKind::linear: gershgorin_run<SpringLawKind::linear>(w, law, k0, k1, rows); break;
      case SpringLawKind::cubic: gershgorin_run<SpringLawKind::cubic>(w, law, k0, k1, rows); break;
      case SpringLawKind::exponential: gershgorin_run<SpringLawKind::exponential>(w, law, k0, k1, rows); break;
    }
  }
}

}  // namespace harness
