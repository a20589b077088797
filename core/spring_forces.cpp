#include "core/spring_forces.hpp"

#include "core/parallel.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define HARNESS_X86_AVX 1
#endif

namespace harness {
namespace {


// The law of a body, chosen at compile time (springs.hpp: the expressions every path shares).
template <SpringLawKind K>
inline double per_length_of(const SpringLaw& law, double L0, double l) {
  if constexpr (K == SpringLawKind::linear) return linear_per_length(law, L0, l);
  if constexpr (K == SpringLawKind::cubic) return cubic_per_length(law, L0, l);
  if constexpr (K == SpringLawKind::exponential) {
    const double x = exponential_arg(law, L0, l);
    return exponential_per_length(law, L0, l, x, spring_expm1(x));
  }
}

constexpr int kChunk = 64;  // half-edges of one node evaluated at a time (stack buffers)
constexpr int kGroup = 4;    // nodes whose sums are interleaved (spring_group_avx)

// Node i's spring force added to acc, one half-edge after the other in spring order; a
// half-edge of zero length adds nothing (the scatter's `if (l <= 0) continue`).
template <SpringLawKind K>
void spring_node(const SpringGather& g, const SpringLaw& law, const Points& x, int i, Vec3& acc) {
  const Vec3 xi = x[i];
  for (int h = g.start[i]; h < g.start[i + 1]; ++h) {
    const Vec3 d = x[g.other[h]] - xi;
    const double l = d.norm();
    if (l <= 0.0) continue;
    acc += per_length_of<K>(law, g.rest[h], l) * d;
  }
}

// The same, evaluating each spring once, for laws whose evaluation dwarfs the rest (the
// exponential: one expm1 per spring). The lower end of a spring whose ends both lie in this
// thread's node range [i0, i1) leaves c in the spring's mailbox slot, and the higher end, which
// comes later in the same thread, reads it; other springs are evaluated at both ends. c is the
// same number either way, so the thread count still changes nothing.
template <SpringLawKind K>
void spring_node_once(const SpringGather& g, const SpringLaw& law, const Points& x, int i, int i0, int i1,
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
      c = per_length_of<K>(law, g.rest[h], l);
      if (j > i && j < i1) box[g.spring[h]] = c;
    }
    acc += c * d;
  }
}

#if defined(HARNESS_X86_AVX)
bool cpu_has_avx() {
  static const bool has = __builtin_cpu_supports("avx");
  return has;
}

// c * (x_j - x_i) of the m half-edges [a, a + m) of node i (m <= kChunk) into FX, FY, FZ;
// returns the mask of those of zero length (they add nothing). Four half-edges per instruction.
template <SpringLawKind K>
__attribute__((target("avx"))) inline std::uint64_t spring_chunk_avx(const SpringGather& g, const SpringLaw& law,
                                                                      const Points& x, const Vec3& xi, int a, int m,
                                                                      double* FX, double* FY, double* FZ) {
  const __m256d x0 = _mm256_set1_pd(xi[0]), x1 = _mm256_set1_pd(xi[1]), x2 = _mm256_set1_pd(xi[2]);
  const __m256d kk = _mm256_set1_pd(law.k), bb = _mm256_set1_pd(law.beta), zero = _mm256_setzero_pd();
  const int* oth = g.other.data() + a;
  const double* L = g.rest.data() + a;
  std::uint64_t skip = 0;  // bit q: half-edge q has zero length
  int q = 0;
  for (; q + 4 <= m; q += 4) {
    const double* p0 = x[oth[q]].data();
    const double* p1 = x[oth[q + 1]].data();
    const double* p2 = x[oth[q + 2]].data();
    const double* p3 = x[oth[q + 3]].data();
    const __m256d dx = _mm256_sub_pd(_mm256_set_pd(p3[0], p2[0], p1[0], p0[0]), x0);
    const __m256d dy = _mm256_sub_pd(_mm256_set_pd(p3[1], p2[1], p1[1], p0[1]), x1);
    const __m256d dz = _mm256_sub_pd(_mm256_set_pd(p3[2], p2[2], p1[2], p0[2]), x2);
    const __m256d l2 =
        _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(dx, dx), _mm256_mul_pd(dy, dy)), _mm256_mul_pd(dz, dz));
    const __m256d l = _mm256_sqrt_pd(l2);
    const __m256d L0 = _mm256_loadu_pd(L + q);
    const __m256d s = _mm256_sub_pd(l, L0);
    __m256d c;  // per_length_of, operation for operation
    if constexpr (K == SpringLawKind::linear) {
      c = _mm256_div_pd(_mm256_mul_pd(kk, s), l);
    } else if constexpr (K == SpringLawKind::cubic) {
      const __m256d L2 = _mm256_mul_pd(L0, L0);
      const __m256d num = _mm256_mul_pd(_mm256_mul_pd(kk, s), _mm256_add_pd(L2, _mm256_mul_pd(_mm256_mul_pd(bb, s), s)));
      c = _mm256_div_pd(num, _mm256_mul_pd(L2, l));
    } else {
      static_assert(K != SpringLawKind::exponential, "evaluated once per spring instead");
    }
    _mm256_store_pd(FX + q, _mm256_mul_pd(c, dx));
    _mm256_store_pd(FY + q, _mm256_mul_pd(c, dy));
    _mm256_store_pd(FZ + q, _mm256_mul_pd(c, dz));
    skip |= static_cast<std::uint64_t>(_mm256_movemask_pd(_mm256_cmp_pd(l, zero, _CMP_LE_OQ))) << q;
  }
  for (; q < m; ++q) {  // the remainder, in this (VEX-encoded) function
    const Vec3 d = x[oth[q]] - xi;
    const double l = d.norm();
    if (l <= 0.0) {
      skip |= std::uint64_t{1} << q;
      continue;
    }
    const double c = per_length_of<K>(law, L[q], l);
    FX[q] = c * d[0], FY[q] = c * d[1], FZ[q] = c * d[2];
  }
  return skip;
}

// The same with AVX where the processor has it (chosen at run time; linear and cubic laws):
// first the force c * (x_other - x_i) of every half-edge of a chunk (spring_chunk_avx); then
// their sum in spring order. Every lane does the scalar operations (d.norm() is
// sqrt((dx^2 + dy^2) + dz^2) in Eigen; no FMA), so the result is the same to the bit.
template <SpringLawKind K>
__attribute__((target("avx"))) void spring_node_avx(const SpringGather& g, const SpringLaw& law, const Points& x,
                                                    int i, Vec3& acc) {
  const Vec3 xi = x[i];
  alignas(32) double FX[kChunk], FY[kChunk], FZ[kChunk];
  double ax = acc[0], ay = acc[1], az = acc[2];
  for (int a = g.start[i]; a < g.start[i + 1]; a += kChunk) {
    const int m = std::min(kChunk, g.start[i + 1] - a);
    const std::uint64_t skip = spring_chunk_avx<K>(g, law, x, xi, a, m, FX, FY, FZ);
    for (int q = 0; q < m; ++q) {
      if ((skip >> q) & 1) continue;
      ax += FX[q], ay += FY[q], az += FZ[q];
    }
  }
  acc = Vec3(ax, ay, az);
  _mm256_zeroupper();
}

// G consecutive nodes i .. i + G - 1 of one body, each with at most kChunk half-edges: their sums
// in spring order interleaved, 3 G independent chains of additions instead of three (the sum,
// not the arithmetic, bounds spring_node_avx: one addition's latency per half-edge). Each
// node's result is spring_node_avx's to the bit.
template <SpringLawKind K, int G>
__attribute__((target("avx"))) void spring_group_avx(const SpringGather& g, const SpringLaw& law, const Points& x,
                                                     int i, Vec3* acc) {
  alignas(32) double F[G][3][kChunk];
  std::uint64_t skip[G];
  int m[G];
  double a[G][3];
  int most = 0;
  for (int n = 0; n < G; ++n) {
    const int first = g.start[i + n];
    m[n] = g.start[i + n + 1] - first;
    most = std::max(most, m[n]);
    skip[n] = spring_chunk_avx<K>(g, law, x, x[i + n], first, m[n], F[n][0], F[n][1], F[n][2]);
    a[n][0] = acc[n][0], a[n][1] = acc[n][1], a[n][2] = acc[n][2];
  }
  for (int q = 0; q < most; ++q)
    for (int n = 0; n < G; ++n)
      if (q < m[n] && !((skip[n] >> q) & 1)) a[n][0] += F[n][0][q], a[n][1] += F[n][1][q], a[n][2] += F[n][2][q];
  for (int n = 0; n < G; ++n) acc[n] = Vec3(a[n][0], a[n][1], a[n][2]);
  _mm256_zeroupper();
}
#endif

// The serial scatter itself (f[i] += F, f[j] -= F in spring order), for the springs of the
// bodies `only` selects (all when null): with one thread it is the fastest form for the
// exponential law, whose expm1 costs more than anything a gather saves.
template <SpringLawKind K>
void scatter_run(const World& w, const SpringLaw& law, std::size_t k0, std::size_t k1, Points& f) {
  const Springs& s = w.springs;
  for (std::size_t k = k0; k < k1; ++k) {
    const int i = s.ends[k][0], j = s.ends[k][1];
    const Vec3 d = w.x[j] - w.x[i];
    const double l = d.norm();
    if (l <= 0.0) continue;  // coincident ends: no defined direction, no force
    const Vec3 fi = per_length_of<K>(law, s.rest[k], l) * d;  // pulls i toward j
    f[i] += fi;
    f[j] -= fi;
  }
}

// The exponential law in blocks: the expm1 of a block at once (spring_expm1_batch, the same bits
// as one at a time), then per_length_of's remaining operations and the scatter in spring order.
template <>
void scatter_run<SpringLawKind::exponential>(const World& w, const SpringLaw& law, std::size_t k0, std::size_t k1,
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
      X[q] = exponential_arg(law, s.rest[k], Lr[q]);
    }
    spring_expm1_batch(X, E, m);
    for (int q = 0; q < m; ++q) {
      const double l = Lr[q];
      if (l <= 0.0) continue;
      const std::size_t k = b + static_cast<std::size_t>(q);
      const double c = exponential_per_length(law, s.rest[k], l, X[q], E[q]);
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
    const SpringLaw& law = w.body_law[b];
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

void gather_spring_forces(SpringGather& g, const World& w, Points& f) {
  const int T = threads_for(static_cast<std::size_t>(g.start[g.nodes]), 32768);
#if defined(HARNESS_X86_AVX)
  const bool avx = cpu_has_avx();
#else
  const bool avx = false;
#endif
  double* box = g.box.data();
  // One thread: exponential bodies by the scatter, the others by the (vectorised) gather. Both
  // give the scatter's bits, and no node has springs of both kinds unless some node is mixed.
  // (Without AVX the gather has nothing to repay its double evaluation on one thread.)
  bool scatter_exp = false;
  if (T == 1) {
    if (!avx || g.mixed_nodes) return scatter_spring_forces(w, f, nullptr);
    if (g.exponential_bodies) {
      scatter_spring_forces(w, f, &g.is_exponential);
      scatter_exp = true;
    }
  }
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
      if (b == -2) continue;
      if (scatter_exp && b >= 0 && g.is_exponential[b]) continue;
      Vec3 acc = f[i];
#if defined(HARNESS_X86_AVX)
      if (avx && b >= 0 && i + kGroup <= i1 && !(scatter_exp && g.is_exponential[b]) &&
          (w.body_law[b].kind == SpringLawKind::linear || w.body_law[b].kind == SpringLawKind::cubic)) {
        bool group = true;
        for (int n = 0; n < kGroup && group; ++n)
          group = g.node_body[i + n] == b && g.start[i + n + 1] - g.start[i + n] <= kChunk;
        if (group) {
          const SpringLaw& law = w.body_law[b];
          Vec3 accs[kGroup];
          for (int n = 0; n < kGroup; ++n) accs[n] = f[i + n];
          if (law.kind == SpringLawKind::linear) spring_group_avx<SpringLawKind::linear, kGroup>(g, law, w.x, i, accs);
          else spring_group_avx<SpringLawKind::cubic, kGroup>(g, law, w.x, i, accs);
          for (int n = 0; n < kGroup; ++n) f[i + n] = accs[n];
          i += kGroup - 1;
          continue;
        }
      }
#endif
      if (b >= 0) {
        const SpringLaw& law = w.body_law[b];
        switch (law.kind) {
#if defined(HARNESS_X86_AVX)
#define HARNESS_SPRING_NODE(K) \
  avx ? spring_node_avx<K>(g, law, w.x, i, acc) : spring_node<K>(g, law, w.x, i, acc)
#else
#define HARNESS_SPRING_NODE(K) spring_node<K>(g, law, w.x, i, acc)
#endif
          case SpringLawKind::linear: HARNESS_SPRING_NODE(SpringLawKind::linear); break;
          case SpringLawKind::cubic: HARNESS_SPRING_NODE(SpringLawKind::cubic); break;
          case SpringLawKind::exponential:
            spring_node_once<SpringLawKind::exponential>(g, law, w.x, i, i0, i1, box, acc);
            break;
#undef HARNESS_SPRING_NODE
        }
      } else {  // springs of several bodies meet here (hand-built worlds): the law per spring
        const Vec3 xi = w.x[i];
        for (int h = g.start[i]; h < g.start[i + 1]; ++h) {
          const int j = g.other[h];
          const Vec3 d = w.x[j] - xi;
          const double l = d.norm();
          if (l <= 0.0) continue;
          const double c = spring_force_per_length(w.body_law[w.springs.body[g.spring[h]]], g.rest[h], l);
          if (j > i && j < i1) box[g.spring[h]] = c;  // for a higher end using spring_node_once
          acc += c * d;
        }
      }
      f[i] = acc;
    }
  }
  (void)avx;
}

// Dashpot forces (c (v_j - v_i).d / l2) d of node i, all springs of damping c (a node of one
// body), four half-edges per AVX instruction and summed in spring order as in spring_node_avx.
// (v_j - v_i).d is ((dvx dx + dvy dy) + dvz dz) in Eigen, as written here.
#if defined(HARNESS_X86_AVX)
__attribute__((target("avx"))) void damping_node_avx(const SpringGather& g, double c, const World& w, int i,
                                                     Vec3& acc) {
  const Vec3 xi = w.x[i], vi = w.v[i];
  const __m256d x0 = _mm256_set1_pd(xi[0]), x1 = _mm256_set1_pd(xi[1]), x2 = _mm256_set1_pd(xi[2]);
  const __m256d v0 = _mm256_set1_pd(vi[0]), v1 = _mm256_set1_pd(vi[1]), v2 = _mm256_set1_pd(vi[2]);
  const __m256d cc = _mm256_set1_pd(c), zero = _mm256_setzero_pd();
  alignas(32) double FX[kChunk], FY[kChunk], FZ[kChunk];
  double ax = acc[0], ay = acc[1], az = acc[2];
  for (int a = g.start[i]; a < g.start[i + 1]; a += kChunk) {
    const int m = std::min(kChunk, g.start[i + 1] - a);
    const int* oth = g.other.data() + a;
    std::uint64_t skip = 0;
    int q = 0;
    for (; q + 4 <= m; q += 4) {
      const double* p0 = w.x[oth[q]].data();
      const double* p1 = w.x[oth[q + 1]].data();
      const double* p2 = w.x[oth[q + 2]].data();
      const double* p3 = w.x[oth[q + 3]].data();
      const double* u0 = w.v[oth[q]].data();
      const double* u1 = w.v[oth[q + 1]].data();
      const double* u2 = w.v[oth[q + 2]].data();
      const double* u3 = w.v[oth[q + 3]].data();
      const __m256d dx = _mm256_sub_pd(_mm256_set_pd(p3[0], p2[0], p1[0], p0[0]), x0);
      const __m256d dy = _mm256_sub_pd(_mm256_set_pd(p3[1], p2[1], p1[1], p0[1]), x1);
      const __m256d dz = _mm256_sub_pd(_mm256_set_pd(p3[2], p2[2], p1[2], p0[2]), x2);
      const __m256d ux = _mm256_sub_pd(_mm256_set_pd(u3[0], u2[0], u1[0], u0[0]), v0);
      const __m256d uy = _mm256_sub_pd(_mm256_set_pd(u3[1], u2[1], u1[1], u0[1]), v1);
      const __m256d uz = _mm256_sub_pd(_mm256_set_pd(u3[2], u2[2], u1[2], u0[2]), v2);
      const __m256d l2 =
          _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(dx, dx), _mm256_mul_pd(dy, dy)), _mm256_mul_pd(dz, dz));
      const __m256d dot =
          _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(ux, dx), _mm256_mul_pd(uy, dy)), _mm256_mul_pd(uz, dz));
      const __m256d s = _mm256_div_pd(_mm256_mul_pd(cc, dot), l2);
      _mm256_store_pd(FX + q, _mm256_mul_pd(s, dx));
      _mm256_store_pd(FY + q, _mm256_mul_pd(s, dy));
      _mm256_store_pd(FZ + q, _mm256_mul_pd(s, dz));
      skip |= static_cast<std::uint64_t>(_mm256_movemask_pd(_mm256_cmp_pd(l2, zero, _CMP_LE_OQ))) << q;
    }
    for (; q < m; ++q) {
      const int j = oth[q];
      const Vec3 d = w.x[j] - xi;
      const double l2 = d.squaredNorm();
      if (l2 <= 0.0) {
        skip |= std::uint64_t{1} << q;
        continue;
      }
      const double sc = c * (w.v[j] - vi).dot(d) / l2;
      FX[q] = sc * d[0], FY[q] = sc * d[1], FZ[q] = sc * d[2];
    }
    for (q = 0; q < m; ++q) {
      if ((skip >> q) & 1) continue;
      ax += FX[q], ay += FY[q], az += FZ[q];
    }
  }
  acc = Vec3(ax, ay, az);
  _mm256_zeroupper();
}
#endif

void gather_damping_forces(const SpringGather& g, const World& w, Points& f) {
  const int T = threads_for(static_cast<std::size_t>(g.start[g.nodes]), 32768);
  if (T == 1) return scatter_damping_forces(w, f);  // the same bits; faster on one thread
#if defined(HARNESS_X86_AVX)
  const bool avx = cpu_has_avx();
#endif
  const int P = T == 1 ? 1 : 4 * T;  // dynamic parts, as for the springs
#pragma omp parallel for num_threads(T) schedule(dynamic, 1)
  for (int t = 0; t < P; ++t) {
    int i0, i1;
    g.part(P, t, i0, i1);
    for (int i = i0; i < i1; ++i) {
      const int owner = g.node_owner[i];
      const double a = owner >= 0 ? w.bodies[owner].material.mass_damping : 0.0;
      const int nb = g.node_body[i];
      const bool dashpots = nb == -1 || (nb >= 0 && w.bodies[nb].material.damping != 0.0);
      if (!dashpots && a == 0.0) continue;
      Vec3 acc = f[i];
#if defined(HARNESS_X86_AVX)
      if (dashpots && nb >= 0 && avx) {
        damping_node_avx(g, w.bodies[nb].material.damping, w, i, acc);
      } else
#endif
      if (dashpots) {
        const Vec3 xi = w.x[i], vi = w.v[i];
        for (int h = g.start[i]; h < g.start[i + 1]; ++h) {
          const double c = nb >= 0 ? w.bodies[nb].material.damping
                                   : w.bodies[w.springs.body[g.spring[h]]].material.damping;
          if (c == 0.0) continue;
          const int j = g.other[h];
          const Vec3 d = w.x[j] - xi;
          const double l2 = d.squaredNorm();
          if (l2 <= 0.0) continue;
          acc += (c * (w.v[j] - vi).dot(d) / l2) * d;  // as the scatter: exactly -F at the other end
        }
      }
      // Mass-proportional damping after every dashpot, as in the serial order.
      if (a != 0.0) acc -= (a * w.m[i]) * w.v[i];
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
      e += spring_energy(w.body_law[s.body[k]], s.rest[k], l);
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
void gershgorin_run(const World& w, const SpringLaw& law, std::size_t k0, std::size_t k1, std::vector<Vec3>& rows) {
  const Springs& s = w.springs;
  for (std::size_t k = k0; k < k1; ++k) {
    const int i = s.ends[k][0], j = s.ends[k][1];
    const Vec3 d = w.x[j] - w.x[i];
    const double l2 = d.squaredNorm();
    if (!(l2 > 0.0)) continue;
    const Vec3 a = d.cwiseAbs();
    const Vec3 r = (2.0 * tangent_over_l2<K>(law, s.rest[k], l2) * a.sum()) * a;
    rows[i] += r;
    rows[j] += r;
  }
}

// The exponential law in blocks, its exp for a block at once (spring_exp_batch).
template <>
void gershgorin_run<SpringLawKind::exponential>(const World& w, const SpringLaw& law, std::size_t k0,
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
      X[q] = L2[q] > 0.0 ? exponential_arg(law, L0, std::sqrt(L2[q])) : 0.0;
    }
    spring_exp_batch(X, E, m);
    for (int q = 0; q < m; ++q) {
      if (!(L2[q] > 0.0)) continue;
      const std::size_t k = b + static_cast<std::size_t>(q);
      const int i = s.ends[k][0], j = s.ends[k][1];
      const Vec3 a = (w.x[j] - w.x[i]).cwiseAbs();
      const Vec3 r = (2.0 * (std::fabs(law.k * E[q]) / L2[q]) * a.sum()) * a;
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
    const SpringLaw& law = w.body_law[b];
    switch (law.kind) {
      case SpringLawKind::linear: gershgorin_run<SpringLawKind::linear>(w, law, k0, k1, rows); break;
      case SpringLawKind::cubic: gershgorin_run<SpringLawKind::cubic>(w, law, k0, k1, rows); break;
      case SpringLawKind::exponential: gershgorin_run<SpringLawKind::exponential>(w, law, k0, k1, rows); break;
    }
  }
}

}  // namespace harness
