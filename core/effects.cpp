#include "core/effects.hpp"

#include "core/parallel.hpp"

#include <algorithm>
#include <cmath>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define HARNESS_X86_AVX 1
#endif

namespace harness {

namespace {

// Node-centric copy of the springs, built once per world. Why a gather: each node's force is
// written by one thread only, and each node sums its springs in spring order -- the order in
// which the serial scatter (f[i] += F, f[j] -= F for spring k = 0, 1, ...) reaches it. The
// force of spring k seen from its second end is computed from d' = x_i - x_j = -d, which gives
// exactly -F (negation, squares and products are sign-symmetric in IEEE arithmetic), so the
// result is bit-identical to the scatter for any thread count. The price is evaluating every
// spring twice, which threads more than repay.
struct SpringGather {
  int nodes = -1;
  std::size_t springs = 0;
  bool with_rest = true;
  std::vector<int> start;        // CSR over half-edges, nodes + 1
  std::vector<int> other;        // the other end of each half-edge
  std::vector<double> rest;      // its spring's rest length, m (with_rest)
  std::vector<int> node_body;    // body of every spring at the node; -1 mixed (see he_body)
  std::vector<int> he_body;      // body of each half-edge's spring, only if some node is mixed
  std::vector<int> node_owner;   // body whose range holds the node, -1 none

  bool matches(const World& w) const { return nodes == w.num_nodes() && springs == w.springs.size(); }

  void build(const World& w, bool keep_rest) {
    const Springs& s = w.springs;
    const int n = w.num_nodes();
    nodes = n;
    springs = s.size();
    with_rest = keep_rest;
    start.assign(static_cast<std::size_t>(n) + 1, 0);
    for (const Edge& e : s.ends) ++start[e[0] + 1], ++start[e[1] + 1];
    for (int i = 0; i < n; ++i) start[i + 1] += start[i];
    const std::size_t H = static_cast<std::size_t>(start[n]);
    other.assign(H, 0);
    rest.assign(keep_rest ? H : 0, 0.0);
    std::vector<int> body(H, 0);
    std::vector<int> cur(start.begin(), start.end() - 1);
    for (std::size_t k = 0; k < s.size(); ++k) {  // spring order: each node's list is sorted by k
      const int i = s.ends[k][0], j = s.ends[k][1];
      const int a = cur[i]++, b = cur[j]++;
      other[a] = j;
      other[b] = i;
      body[a] = body[b] = s.body[k];
      if (keep_rest) rest[a] = rest[b] = s.rest[k];
    }
    node_body.assign(static_cast<std::size_t>(n), -1);
    bool mixed = false;
    for (int i = 0; i < n; ++i) {
      if (start[i] == start[i + 1]) continue;
      int b = body[start[i]];
      for (int h = start[i] + 1; h < start[i + 1]; ++h)
        if (body[h] != b) b = -1;
      node_body[i] = b;
      mixed = mixed || b < 0;
    }
    if (mixed) he_body.swap(body);
    else he_body.clear();
    node_owner.assign(static_cast<std::size_t>(n), -1);
    for (std::size_t b = 0; b < w.bodies.size(); ++b)
      for (int i = std::max(0, w.bodies[b].begin); i < std::min(n, w.bodies[b].end); ++i)
        node_owner[i] = static_cast<int>(b);
  }

  // Node range of part t of T with about equal numbers of half-edges (never depends on the
  // results, only on how work is shared).
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

// Spring laws inlined for the hot loop: the very expressions of spring_tension (springs.cpp),
// so the results are bit-identical (tests/core/test_parallel.cpp compares them).
inline double expm1_over_x_inline(double x) {
  if (std::fabs(x) < 1e-8) return 1.0 + 0.5 * x;
  return std::expm1(x) / x;
}
template <SpringLawKind K>
inline double tension_of(const SpringLaw& law, double L0, double l) {
  const double eps = (l - L0) / L0;
  if constexpr (K == SpringLawKind::linear) return law.k * L0 * eps;
  if constexpr (K == SpringLawKind::cubic) return law.k * L0 * (eps + law.beta * eps * eps * eps);
  if constexpr (K == SpringLawKind::exponential) return law.k * L0 * eps * expm1_over_x_inline(law.beta * eps);
}

template <SpringLawKind K>
inline void spring_node_scalar(const SpringGather& g, const SpringLaw& law, const Points& x, int i, int h,
                               Vec3& acc) {
  const Vec3 xi = x[i];
  for (; h < g.start[i + 1]; ++h) {
    const Vec3 d = x[g.other[h]] - xi;
    const double l = d.norm();
    if (l <= 0.0) continue;  // coincident ends: no defined direction, no force
    const double t = tension_of<K>(law, g.rest[h], l);
    acc += (t / l) * d;  // tension pulls i toward the other end
  }
}

#if defined(__SSE2__)
// Two springs of node i at a time: the square roots and divisions (the cost of a spring) run
// in pairs; the products are added to the node's force one spring after the other, in spring
// order, so every operation and its order is that of spring_node_scalar (IEEE arithmetic is
// exact per lane; d.norm() is sqrt((dx^2 + dy^2) + dz^2) in Eigen).
template <SpringLawKind K>
inline void spring_node(const SpringGather& g, const SpringLaw& law, const Points& x, int i, int h, Vec3& acc) {
  const Vec3& xi = x[i];
  const __m128d x0 = _mm_set1_pd(xi[0]), x1 = _mm_set1_pd(xi[1]), x2 = _mm_set1_pd(xi[2]);
  const __m128d kk = _mm_set1_pd(law.k), bb = _mm_set1_pd(law.beta), zero = _mm_setzero_pd();
  double ax = acc[0], ay = acc[1], az = acc[2];
  const int he = g.start[i + 1];
  for (; h + 2 <= he; h += 2) {
    const Vec3& p = x[g.other[h]];
    const Vec3& q = x[g.other[h + 1]];
    const __m128d dx = _mm_sub_pd(_mm_set_pd(q[0], p[0]), x0);
    const __m128d dy = _mm_sub_pd(_mm_set_pd(q[1], p[1]), x1);
    const __m128d dz = _mm_sub_pd(_mm_set_pd(q[2], p[2]), x2);
    const __m128d l2 = _mm_add_pd(_mm_add_pd(_mm_mul_pd(dx, dx), _mm_mul_pd(dy, dy)), _mm_mul_pd(dz, dz));
    const __m128d l = _mm_sqrt_pd(l2);
    const __m128d L0 = _mm_loadu_pd(&g.rest[h]);
    const __m128d eps = _mm_div_pd(_mm_sub_pd(l, L0), L0);
    const __m128d kL0 = _mm_mul_pd(kk, L0);
    __m128d t;
    if constexpr (K == SpringLawKind::linear) {
      t = _mm_mul_pd(kL0, eps);
    } else if constexpr (K == SpringLawKind::cubic) {
      t = _mm_mul_pd(kL0, _mm_add_pd(eps, _mm_mul_pd(_mm_mul_pd(_mm_mul_pd(bb, eps), eps), eps)));
    } else {
      alignas(16) double be[2];
      _mm_store_pd(be, _mm_mul_pd(bb, eps));
      t = _mm_mul_pd(_mm_mul_pd(kL0, eps), _mm_set_pd(expm1_over_x_inline(be[1]), expm1_over_x_inline(be[0])));
    }
    const __m128d c = _mm_div_pd(t, l);
    alignas(16) double fx[2], fy[2], fz[2];
    _mm_store_pd(fx, _mm_mul_pd(c, dx));
    _mm_store_pd(fy, _mm_mul_pd(c, dy));
    _mm_store_pd(fz, _mm_mul_pd(c, dz));
    // Lanes with l <= 0 are skipped (as `continue`; a NaN length is not skipped, as there).
    const int skip = _mm_movemask_pd(_mm_cmple_pd(l, zero));
    if (!(skip & 1)) ax += fx[0], ay += fy[0], az += fz[0];
    if (!(skip & 2)) ax += fx[1], ay += fy[1], az += fz[1];
  }
  acc = Vec3(ax, ay, az);
  if (h < he) spring_node_scalar<K>(g, law, x, i, h, acc);
}
#else
template <SpringLawKind K>
inline void spring_node(const SpringGather& g, const SpringLaw& law, const Points& x, int i, int h, Vec3& acc) {
  spring_node_scalar<K>(g, law, x, i, h, acc);
}
#endif

#if defined(HARNESS_X86_AVX)
// Four springs at a time with AVX where the processor has it (chosen at run time); the same
// operations in the same order as above, so the same bits. No FMA: contraction would change them.
template <SpringLawKind K>
__attribute__((target("avx"))) void spring_node_avx(const SpringGather& g, const SpringLaw& law, const Points& x,
                                                    int i, Vec3& acc) {
  const Vec3& xi = x[i];
  const __m256d x0 = _mm256_set1_pd(xi[0]), x1 = _mm256_set1_pd(xi[1]), x2 = _mm256_set1_pd(xi[2]);
  const __m256d kk = _mm256_set1_pd(law.k), bb = _mm256_set1_pd(law.beta), zero = _mm256_setzero_pd();
  double ax = acc[0], ay = acc[1], az = acc[2];
  int h = g.start[i];
  const int he = g.start[i + 1];
  for (; h + 4 <= he; h += 4) {
    const double* p0 = x[g.other[h]].data();
    const double* p1 = x[g.other[h + 1]].data();
    const double* p2 = x[g.other[h + 2]].data();
    const double* p3 = x[g.other[h + 3]].data();
    const __m256d dx = _mm256_sub_pd(_mm256_set_pd(p3[0], p2[0], p1[0], p0[0]), x0);
    const __m256d dy = _mm256_sub_pd(_mm256_set_pd(p3[1], p2[1], p1[1], p0[1]), x1);
    const __m256d dz = _mm256_sub_pd(_mm256_set_pd(p3[2], p2[2], p1[2], p0[2]), x2);
    const __m256d l2 =
        _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(dx, dx), _mm256_mul_pd(dy, dy)), _mm256_mul_pd(dz, dz));
    const __m256d l = _mm256_sqrt_pd(l2);
    const __m256d L0 = _mm256_loadu_pd(&g.rest[h]);
    const __m256d eps = _mm256_div_pd(_mm256_sub_pd(l, L0), L0);
    const __m256d kL0 = _mm256_mul_pd(kk, L0);
    __m256d t;
    if constexpr (K == SpringLawKind::linear) {
      t = _mm256_mul_pd(kL0, eps);
    } else if constexpr (K == SpringLawKind::cubic) {
      t = _mm256_mul_pd(kL0, _mm256_add_pd(eps, _mm256_mul_pd(_mm256_mul_pd(_mm256_mul_pd(bb, eps), eps), eps)));
    } else {
      alignas(32) double be[4];
      _mm256_store_pd(be, _mm256_mul_pd(bb, eps));
      t = _mm256_mul_pd(_mm256_mul_pd(kL0, eps),
                        _mm256_set_pd(expm1_over_x_inline(be[3]), expm1_over_x_inline(be[2]),
                                      expm1_over_x_inline(be[1]), expm1_over_x_inline(be[0])));
    }
    const __m256d c = _mm256_div_pd(t, l);
    alignas(32) double fx[4], fy[4], fz[4];
    _mm256_store_pd(fx, _mm256_mul_pd(c, dx));
    _mm256_store_pd(fy, _mm256_mul_pd(c, dy));
    _mm256_store_pd(fz, _mm256_mul_pd(c, dz));
    const int skip = _mm256_movemask_pd(_mm256_cmp_pd(l, zero, _CMP_LE_OQ));
    for (int q = 0; q < 4; ++q)
      if (!((skip >> q) & 1)) ax += fx[q], ay += fy[q], az += fz[q];
  }
  acc = Vec3(ax, ay, az);
  if (h < he) spring_node<K>(g, law, x, i, h, acc);
}

bool cpu_has_avx() {
  static const bool has = __builtin_cpu_supports("avx");
  return has;
}
#endif

template <SpringLawKind K>
inline void spring_node_best(const SpringGather& g, const SpringLaw& law, const Points& x, int i, bool avx,
                             Vec3& acc) {
#if defined(HARNESS_X86_AVX)
  if (avx) return spring_node_avx<K>(g, law, x, i, acc);
#endif
  (void)avx;
  spring_node<K>(g, law, x, i, g.start[i], acc);
}

void gather_spring_forces(const SpringGather& g, const World& w, Points& f) {
  const int T = threads_for(static_cast<std::size_t>(g.start[g.nodes]), 32768);
#if defined(HARNESS_X86_AVX)
  const bool avx = cpu_has_avx();
#else
  const bool avx = false;
#endif
#pragma omp parallel for num_threads(T) schedule(static, 1)
  for (int t = 0; t < T; ++t) {
    int i0, i1;
    g.part(T, t, i0, i1);
    for (int i = i0; i < i1; ++i) {
      const int b = g.node_body[i];
      if (g.start[i] == g.start[i + 1]) continue;
      Vec3 acc = f[i];
      if (b >= 0) {
        const SpringLaw& law = w.body_law[b];
        switch (law.kind) {
          case SpringLawKind::linear: spring_node_best<SpringLawKind::linear>(g, law, w.x, i, avx, acc); break;
          case SpringLawKind::cubic: spring_node_best<SpringLawKind::cubic>(g, law, w.x, i, avx, acc); break;
          case SpringLawKind::exponential:
            spring_node_best<SpringLawKind::exponential>(g, law, w.x, i, avx, acc);
            break;
        }
      } else {  // springs of several bodies meet here (hand-built worlds): the law per spring
        for (int h = g.start[i]; h < g.start[i + 1]; ++h) {
          const Vec3 d = w.x[g.other[h]] - w.x[i];
          const double l = d.norm();
          if (l <= 0.0) continue;
          const double tension = spring_tension(w.body_law[g.he_body[h]], g.rest[h], l);
          acc += (tension / l) * d;
        }
      }
      f[i] = acc;
    }
  }
}

void gather_damping_forces(const SpringGather& g, const World& w, Points& f) {
  const int T = threads_for(static_cast<std::size_t>(g.start[g.nodes]), 32768);
#pragma omp parallel for num_threads(T) schedule(static, 1)
  for (int t = 0; t < T; ++t) {
    int i0, i1;
    g.part(T, t, i0, i1);
    for (int i = i0; i < i1; ++i) {
      const int owner = g.node_owner[i];
      const double a = owner >= 0 ? w.bodies[owner].material.mass_damping : 0.0;
      const int nb = g.node_body[i];
      const bool springs = g.start[i] != g.start[i + 1] && (nb < 0 || w.bodies[nb].material.damping != 0.0);
      if (!springs && a == 0.0) continue;
      Vec3 acc = f[i];
      if (springs) {
        const Vec3 xi = w.x[i], vi = w.v[i];
        for (int h = g.start[i]; h < g.start[i + 1]; ++h) {
          const double c = w.bodies[nb >= 0 ? nb : g.he_body[h]].material.damping;
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

void add_spring_forces(const World& w, Points& f) {
  SpringGather g;
  g.build(w, true);
  gather_spring_forces(g, w, f);
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

void add_damping_forces(const World& w, Points& f) {
  SpringGather g;
  g.build(w, false);
  gather_damping_forces(g, w, f);
}

void add_gravity_forces(const World& w, const Vec3& g, Points& f) {
  const int n = w.num_nodes();
#pragma omp parallel for num_threads(threads_for(static_cast<std::size_t>(n))) schedule(static)
  for (int i = 0; i < n; ++i) f[i] += w.m[i] * g;
}

void add_pressure_forces(const World& w, int body, double p, Points& f) {
  const Body& b = w.bodies[body];
  const double s = p / 6.0;  // area vector = cross/2, a third to each vertex
  for (const Tri& t : b.faces) {
    const int i = b.begin + t[0], j = b.begin + t[1], k = b.begin + t[2];
    const Vec3 fn = s * (w.x[j] - w.x[i]).cross(w.x[k] - w.x[i]);
    f[i] += fn;
    f[j] += fn;
    f[k] += fn;
  }
}

double ramp_pressure(const PressureSpec& p, int step) {
  if (p.ramp_steps <= 0 || step >= p.ramp_steps) return p.to;
  const double a = static_cast<double>(std::max(step, 0)) / p.ramp_steps;
  return p.from + (p.to - p.from) * a;
}

namespace {

// The effects keep their gather between steps (built on the first step; rebuilt only if the
// number of nodes or springs changes: topology and rest lengths are fixed once a world is built).
class SpringsEffect final : public ForceEffect {
 public:
  const char* name() const override { return "springs"; }
  void apply(World& w, const StepInfo&) override {
    if (!gather_.matches(w)) gather_.build(w, true);
    gather_spring_forces(gather_, w, w.f);
  }
  double energy(const World& w) const override { return spring_potential(w); }

 private:
  SpringGather gather_;
};

class DampingEffect final : public ForceEffect {
 public:
  const char* name() const override { return "damping"; }
  void apply(World& w, const StepInfo&) override {
    if (!gather_.matches(w)) gather_.build(w, false);
    gather_damping_forces(gather_, w, w.f);
  }

 private:
  SpringGather gather_;
};

class GravityEffect final : public ForceEffect {
 public:
  explicit GravityEffect(const Vec3& g) : g_(g) {}
  const char* name() const override { return "gravity"; }
  void apply(World& w, const StepInfo&) override { add_gravity_forces(w, g_, w.f); }
  double energy(const World& w) const override {
    double e = 0.0;
    for (int i = 0; i < w.num_nodes(); ++i) e -= w.m[i] * g_.dot(w.x[i]);
    return e;
  }

 private:
  Vec3 g_;
};

class PressureEffect final : public ForceEffect {
 public:
  explicit PressureEffect(std::vector<std::pair<int, PressureSpec>> b) : bodies_(std::move(b)) {}
  const char* name() const override { return "pressure"; }
  void apply(World& w, const StepInfo& s) override {
    for (const auto& [body, spec] : bodies_) add_pressure_forces(w, body, ramp_pressure(spec, s.step), w.f);
  }

 private:
  std::vector<std::pair<int, PressureSpec>> bodies_;
};

}  // namespace

std::unique_ptr<ForceEffect> make_springs_effect() { return std::make_unique<SpringsEffect>(); }
std::unique_ptr<ForceEffect> make_damping_effect() { return std::make_unique<DampingEffect>(); }
std::unique_ptr<ForceEffect> make_gravity_effect(const Vec3& g) { return std::make_unique<GravityEffect>(g); }
std::unique_ptr<ForceEffect> make_pressure_effect(std::vector<std::pair<int, PressureSpec>> bodies) {
  return std::make_unique<PressureEffect>(std::move(bodies));
}

}  // namespace harness
