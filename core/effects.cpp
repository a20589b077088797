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

// Node-centric view of the springs, built once per world: for every node, its half-edges (the
// other end and the spring's index) in spring order.
//
// Why a gather: each node's force is written by one thread only, and each node sums its springs
// in spring order -- the order in which the serial scatter (f[i] += F, f[j] -= F for spring
// k = 0, 1, ...) reaches it. Every half-edge adds c * (x_other - x_self), c = tension / length
// (or, for a dashpot, the damping coefficient times the relative speed over the length): seen
// from the second end that is exactly -F, since negation, squares and products are sign-
// symmetric in IEEE arithmetic. So the forces are bit-identical to the serial scatter, for any
// thread count.
//
// Each spring's c is computed once (its square root and divisions are the cost of a spring):
// the lower end computes it and leaves it in a mailbox (box, one slot per spring) that the
// higher end reads, when both ends lie in the same thread's node range (otherwise both ends
// compute it: the same value either way, so the thread count still changes nothing). The
// higher end reads its slot within a few lattice planes of nodes, while it is still cached.
struct SpringGather {
  int nodes = -1;
  std::size_t springs = 0;
  std::vector<int> start;        // CSR over half-edges, nodes + 1
  std::vector<int> other;        // the other end of each half-edge
  std::vector<int> spring;       // its spring's index in World::springs
  std::vector<int> node_body;    // body of every spring at the node; -1 mixed, -2 no springs
  std::vector<int> node_owner;   // body whose range holds the node, -1 none
  std::vector<double> box;       // per spring: c from the lower end (scratch of apply)

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
    std::vector<int> cur(start.begin(), start.end() - 1);
    for (std::size_t k = 0; k < s.size(); ++k) {  // spring order: each node's list is sorted by k
      const int i = s.ends[k][0], j = s.ends[k][1];
      const int a = cur[i]++, b = cur[j]++;
      other[a] = j;
      other[b] = i;
      spring[a] = spring[b] = static_cast<int>(k);
    }
    node_body.assign(static_cast<std::size_t>(n), -2);
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

constexpr int kChunk = 64;  // half-edges of one node handled at a time (stack buffers)

// Coefficients c = tension / length of the half-edges cid[0..nc) of a chunk (other, spring:
// the chunk's arrays; cl: the chunk's coefficients), at node position xi.
template <SpringLawKind K>
void spring_coefs(const SpringLaw& law, const double* rest, const Points& x, const Vec3& xi, const int* other,
                  const int* spring, const int* cid, int nc, double* cl) {
  for (int r = 0; r < nc; ++r) {
    const int q = cid[r];
    const double l = (x[other[q]] - xi).norm();
    cl[q] = tension_of<K>(law, rest[spring[q]], l) / l;
  }
}

#if defined(HARNESS_X86_AVX)
// Four at a time with AVX where the processor has it (chosen at run time): the same operations
// on each lane (d.norm() is sqrt((dx^2 + dy^2) + dz^2) in Eigen), so the same bits. No FMA:
// contraction would change them.
template <SpringLawKind K>
__attribute__((target("avx"))) void spring_coefs_avx(const SpringLaw& law, const double* rest, const Points& x,
                                                     const Vec3& xi, const int* other, const int* spring,
                                                     const int* cid, int nc, double* cl) {
  const __m256d x0 = _mm256_set1_pd(xi[0]), x1 = _mm256_set1_pd(xi[1]), x2 = _mm256_set1_pd(xi[2]);
  const __m256d kk = _mm256_set1_pd(law.k), bb = _mm256_set1_pd(law.beta);
  int r = 0;
  for (; r + 4 <= nc; r += 4) {
    const int q0 = cid[r], q1 = cid[r + 1], q2 = cid[r + 2], q3 = cid[r + 3];
    const double* p0 = x[other[q0]].data();
    const double* p1 = x[other[q1]].data();
    const double* p2 = x[other[q2]].data();
    const double* p3 = x[other[q3]].data();
    const __m256d dx = _mm256_sub_pd(_mm256_set_pd(p3[0], p2[0], p1[0], p0[0]), x0);
    const __m256d dy = _mm256_sub_pd(_mm256_set_pd(p3[1], p2[1], p1[1], p0[1]), x1);
    const __m256d dz = _mm256_sub_pd(_mm256_set_pd(p3[2], p2[2], p1[2], p0[2]), x2);
    const __m256d l2 =
        _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(dx, dx), _mm256_mul_pd(dy, dy)), _mm256_mul_pd(dz, dz));
    const __m256d l = _mm256_sqrt_pd(l2);
    const __m256d L0 = _mm256_set_pd(rest[spring[q3]], rest[spring[q2]], rest[spring[q1]], rest[spring[q0]]);
    const __m256d eps = _mm256_div_pd(_mm256_sub_pd(l, L0), L0);
    const __m256d kL0 = _mm256_mul_pd(kk, L0);
    __m256d t;
    if constexpr (K == SpringLawKind::linear) {
      t = _mm256_mul_pd(kL0, eps);
    } else if constexpr (K == SpringLawKind::cubic) {
      t = _mm256_mul_pd(kL0, _mm256_add_pd(eps, _mm256_mul_pd(_mm256_mul_pd(_mm256_mul_pd(bb, eps), eps), eps)));
    } else {
      alignas(32) double be[4], ex[4];
      _mm256_store_pd(be, _mm256_mul_pd(bb, eps));
      if ((std::fabs(be[0]) < 1e-8) & (std::fabs(be[1]) < 1e-8) & (std::fabs(be[2]) < 1e-8) &
          (std::fabs(be[3]) < 1e-8)) {
        for (int e = 0; e < 4; ++e) ex[e] = 1.0 + 0.5 * be[e];
      } else {
        _mm256_zeroupper();  // expm1 is legacy-SSE code (see below)
        for (int e = 0; e < 4; ++e) ex[e] = expm1_over_x_inline(be[e]);
      }
      t = _mm256_mul_pd(_mm256_mul_pd(kL0, eps), _mm256_load_pd(ex));
    }
    const __m256d c = _mm256_div_pd(t, l);
    const __m128d c01 = _mm256_castpd256_pd128(c), c23 = _mm256_extractf128_pd(c, 1);
    _mm_storel_pd(cl + q0, c01);
    _mm_storeh_pd(cl + q1, c01);
    _mm_storel_pd(cl + q2, c23);
    _mm_storeh_pd(cl + q3, c23);
  }
  // The rest here, in VEX code: returning to (or calling) legacy-SSE code with the upper halves
  // of the ymm registers dirty costs a false dependency on every SSE instruction.
  for (; r < nc; ++r) {
    const int q = cid[r];
    const double l = (x[other[q]] - xi).norm();
    cl[q] = tension_of<K>(law, rest[spring[q]], l) / l;
  }
  _mm256_zeroupper();
}

bool cpu_has_avx() {
  static const bool has = __builtin_cpu_supports("avx");
  return has;
}
#endif

// Adds c * (x_other - x_i) of node i's half-edges to acc in spring order, kChunk half-edges at
// a time (nodes with more half-edges than a block; see gather_range).
template <class Coefs, class Skip>
inline void gather_node(const SpringGather& g, const Points& x, int i, int i0, int i1, Vec3& acc, Coefs&& coefs,
                        Skip&& skip) {
  const Vec3 xi = x[i];
  int cid[kChunk];
  double cl[kChunk];
  double* box = const_cast<double*>(g.box.data());  // each slot written by one thread (see above)
  for (int a = g.start[i]; a < g.start[i + 1]; a += kChunk) {
    const int m = std::min(kChunk, g.start[i + 1] - a);
    const int* oth = g.other.data() + a;
    const int* spr = g.spring.data() + a;
    int nc = 0;
    for (int q = 0; q < m; ++q) {
      const int j = oth[q];
      if (j < i && j >= i0) cl[q] = box[spr[q]];  // published by the lower end, this thread
      else cid[nc++] = q;
    }
    coefs(i, a, cid, nc, cl);
    for (int r = 0; r < nc; ++r) {
      const int q = cid[r], j = oth[q];
      if (j > i && j < i1) box[spr[q]] = cl[q];
    }
    for (int q = 0; q < m; ++q) {
      const Vec3 d = x[oth[q]] - xi;
      if (d.squaredNorm() <= 0.0 || skip(i, a + q)) continue;
      acc += cl[q] * d;
    }
  }
}

constexpr int kBlock = 1024;  // half-edges per block: the coefficient buffer is 8 KiB

// One thread's nodes [i0, i1), in blocks of whole nodes with at most kBlock half-edges: first
// the coefficient of every half-edge of the block (from the mailbox, or coefs(i, a, cid, nc, cl)
// for half-edges a + cid[r] of node i), then each node's sum in spring order. Keeping the two
// apart puts many independent square roots and divisions in flight. A zero-length half-edge
// adds nothing (the scatter's `l <= 0`: sqrt(l2) <= 0 exactly when l2 <= 0), nor does one the
// scatter skips (`skip(i, h)`); finish(i, acc) stores the node's force.
template <class Active, class Coefs, class Skip, class Finish>
void gather_range(const SpringGather& g, const Points& x, int i0, int i1, Active&& active, Coefs&& coefs,
                  Skip&& skip, Finish&& finish, const Points& f) {
  double* box = const_cast<double*>(g.box.data());
  int cid[kBlock];
  double cl[kBlock];
  int i = i0;
  while (i < i1) {
    const int H0 = g.start[i];
    if (g.start[i + 1] - H0 > kBlock) {  // a node longer than a block: on its own, in chunks
      Vec3 acc = f[i];
      if (active(i)) gather_node(g, x, i, i0, i1, acc, coefs, skip);
      finish(i, acc);
      ++i;
      continue;
    }
    int e = i + 1;
    while (e < i1 && g.start[e + 1] - H0 <= kBlock) ++e;
    for (int n = i; n < e; ++n) {
      if (!active(n)) continue;
      const int a = g.start[n], m = g.start[n + 1] - a;
      const int* oth = g.other.data() + a;
      const int* spr = g.spring.data() + a;
      double* c = cl + (a - H0);
      int nc = 0;
      for (int q = 0; q < m; ++q) {
        const int j = oth[q];
        if (j < n && j >= i0) c[q] = box[spr[q]];  // published by the lower end, this thread
        else cid[nc++] = q;
      }
      coefs(n, a, cid, nc, c);
      for (int r = 0; r < nc; ++r) {
        const int q = cid[r], j = oth[q];
        if (j > n && j < i1) box[spr[q]] = c[q];
      }
    }
    for (int n = i; n < e; ++n) {
      Vec3 acc = f[n];
      if (active(n)) {
        const Vec3 xn = x[n];
        for (int h = g.start[n]; h < g.start[n + 1]; ++h) {
          const Vec3 d = x[g.other[h]] - xn;
          if (d.squaredNorm() <= 0.0 || skip(n, h)) continue;
          acc += cl[h - H0] * d;
        }
      }
      finish(n, acc);
    }
    i = e;
  }
}

void gather_spring_forces(SpringGather& g, const World& w, Points& f) {
  const int T = threads_for(static_cast<std::size_t>(g.start[g.nodes]), 32768);
#if defined(HARNESS_X86_AVX)
  const bool avx = cpu_has_avx();
#endif
  const double* rest = w.springs.rest.data();
  auto coefs = [&](int i, int a, const int* cid, int nc, double* cl) {
    const int* oth = &g.other[a];
    const int* spr = &g.spring[a];
    const Vec3& xi = w.x[i];
    const int b = g.node_body[i];
    if (b < 0) {  // springs of several bodies meet here (hand-built worlds): the law per spring
      for (int r = 0; r < nc; ++r) {
        const int q = cid[r], k = spr[q];
        const double l = (w.x[oth[q]] - xi).norm();
        cl[q] = spring_tension(w.body_law[w.springs.body[k]], rest[k], l) / l;
      }
      return;
    }
    const SpringLaw& law = w.body_law[b];
#if defined(HARNESS_X86_AVX)
    if (avx) {
      switch (law.kind) {
        case SpringLawKind::linear:
          return spring_coefs_avx<SpringLawKind::linear>(law, rest, w.x, xi, oth, spr, cid, nc, cl);
        case SpringLawKind::cubic:
          return spring_coefs_avx<SpringLawKind::cubic>(law, rest, w.x, xi, oth, spr, cid, nc, cl);
        case SpringLawKind::exponential:
          return spring_coefs_avx<SpringLawKind::exponential>(law, rest, w.x, xi, oth, spr, cid, nc, cl);
      }
    }
#endif
    switch (law.kind) {
      case SpringLawKind::linear: return spring_coefs<SpringLawKind::linear>(law, rest, w.x, xi, oth, spr, cid, nc, cl);
      case SpringLawKind::cubic: return spring_coefs<SpringLawKind::cubic>(law, rest, w.x, xi, oth, spr, cid, nc, cl);
      case SpringLawKind::exponential:
        return spring_coefs<SpringLawKind::exponential>(law, rest, w.x, xi, oth, spr, cid, nc, cl);
    }
  };
#pragma omp parallel for num_threads(T) schedule(static, 1)
  for (int t = 0; t < T; ++t) {
    int i0, i1;
    g.part(T, t, i0, i1);
    gather_range(
        g, w.x, i0, i1, [&](int i) { return g.node_body[i] != -2; }, coefs, [](int, int) { return false; },
        [&](int i, const Vec3& acc) { f[i] = acc; }, f);
  }
}

void gather_damping_forces(SpringGather& g, const World& w, Points& f) {
  const int T = threads_for(static_cast<std::size_t>(g.start[g.nodes]), 32768);
  auto damping_of = [&](int h) { return w.bodies[w.springs.body[g.spring[h]]].material.damping; };
  // A node whose springs all have c = 0 neither computes nor reads a dashpot (nor does the other
  // end of any of them: same spring, same c).
  auto active = [&](int i) {
    const int nb = g.node_body[i];
    return nb == -1 || (nb >= 0 && w.bodies[nb].material.damping != 0.0);
  };
  auto coefs = [&](int i, int a, const int* cid, int nc, double* cl) {
    const Vec3 xi = w.x[i], vi = w.v[i];
    for (int r = 0; r < nc; ++r) {
      const int q = cid[r], j = g.other[a + q];
      const Vec3 d = w.x[j] - xi;
      // As the scatter: (c (v_j - v_i).d / l2) d, exactly -F from the other end.
      cl[q] = damping_of(a + q) * (w.v[j] - vi).dot(d) / d.squaredNorm();
    }
  };
  // Springs without damping at nodes where bodies meet are skipped, as the scatter does.
  auto skip = [&](int i, int h) { return g.node_body[i] == -1 && damping_of(h) == 0.0; };
  auto finish = [&](int i, const Vec3& acc) {
    const int owner = g.node_owner[i];
    const double a = owner >= 0 ? w.bodies[owner].material.mass_damping : 0.0;
    if (!active(i) && a == 0.0) return;
    // Mass-proportional damping after every dashpot, as in the serial order.
    f[i] = a != 0.0 ? Vec3(acc - (a * w.m[i]) * w.v[i]) : acc;
  };
#pragma omp parallel for num_threads(T) schedule(static, 1)
  for (int t = 0; t < T; ++t) {
    int i0, i1;
    g.part(T, t, i0, i1);
    gather_range(g, w.x, i0, i1, active, coefs, skip, finish, f);
  }
}

}  // namespace

void add_spring_forces(const World& w, Points& f) {
  SpringGather g;
  g.build(w);
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
  g.build(w);
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
// number of nodes or springs changes: the topology is fixed once a world is built; rest
// lengths and materials are read from the World every step).
class SpringsEffect final : public ForceEffect {
 public:
  const char* name() const override { return "springs"; }
  void apply(World& w, const StepInfo&) override {
    if (!gather_.matches(w)) gather_.build(w);
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
    if (!gather_.matches(w)) gather_.build(w);
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
