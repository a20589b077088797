#include "core/spring_forces.hpp"

#include "core/cpu.hpp"
#include "core/parallel.hpp"
#include "core/simd/kernels.hpp"
#include "core/springs.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace harness {

static_assert(sizeof(Vec3) == 3 * sizeof(double), "the kernels take points as three packed doubles");

namespace {
constexpr int kPad = 4;                // padding entries past the index arrays and the box
constexpr int kBlock = 512;            // nodes evaluated, then summed, at a time (in cache)
// Half-edges per thread below which the pass stays on one thread (a parallel region costs a few
// microseconds: about 10 us of work per thread at 1 ns per half-edge).
constexpr std::size_t kHalfEdgesPerThread = 8192;
}  // namespace

void SpringGather::build(const World& w) {
  const Springs& s = w.springs;
  const int n = w.num_nodes();
  nodes = n;
  springs = s.size();
  // Which end of spring k is its upper half-edge: the lower-index end (the first end of a spring
  // on one node).
  auto upper_at = [&](std::size_t k, int end) {
    const int i = s.ends[k][0], j = s.ends[k][1];
    return end == 0 ? i <= j : j < i;
  };
  up_start.assign(static_cast<std::size_t>(n) + 1, 0);
  lo_start.assign(static_cast<std::size_t>(n) + 1, 0);
  for (std::size_t k = 0; k < s.size(); ++k)
    for (int end = 0; end < 2; ++end) ++(upper_at(k, end) ? up_start : lo_start)[s.ends[k][end] + 1];
  for (int i = 0; i < n; ++i) up_start[i + 1] += up_start[i], lo_start[i + 1] += lo_start[i];
  const std::size_t U = static_cast<std::size_t>(up_start[n]), L = static_cast<std::size_t>(lo_start[n]);
  up_self.assign(U + kPad, 0), up_other.assign(U + kPad, 0), up_spring.assign(U + kPad, 0);
  up_rest.assign(U + kPad, 1.0), up_inv_rest.assign(U + kPad, 1.0), up_stiff.assign(U + kPad, 0.0);
  lo_slot.assign(L + kPad, 0);
  std::vector<int> cu(up_start.begin(), up_start.end() - 1), cl(lo_start.begin(), lo_start.end() - 1);
  std::vector<int> slot_of(s.size(), -1);
  for (std::size_t k = 0; k < s.size(); ++k)  // spring order: each list is sorted by k
    for (int end = 0; end < 2; ++end)
      if (upper_at(k, end)) {
        const int self = s.ends[k][end];
        const int h = cu[self]++;
        up_self[h] = self, up_other[h] = s.ends[k][1 - end], up_spring[h] = static_cast<int>(k);
        up_rest[h] = s.rest[k], up_inv_rest[h] = 1.0 / s.rest[k], up_stiff[h] = s.k[k];
        slot_of[k] = h;
      }
  for (std::size_t k = 0; k < s.size(); ++k)
    for (int end = 0; end < 2; ++end) {
      if (upper_at(k, end)) continue;
      const int h = cl[s.ends[k][end]]++;
      lo_slot[h] = slot_of[k];
    }
  // Four doubles per upper half-edge (x y z 0), the entries from a 32-byte boundary (box()).
  F.assign(4 * (U + kPad) + 4, 0.0), G.assign(4 * (U + kPad) + 4, 0.0), R.assign(4 * (U + kPad) + 4, 0.0);
  e.assign(U + kPad, 0.0);
  splits.clear();
  chunk_bounds.clear();
  // Runs: each body's upper half-edges; mixed when a spring's upper end lies outside its body.
  runs.clear();
  mixed = false;
  for (std::size_t b = 0; b < w.bodies.size(); ++b) {
    const Body& body = w.bodies[b];
    const int lo = std::clamp(body.begin, 0, n), hi = std::clamp(body.end, lo, n);
    for (int h = up_start[lo]; h < up_start[hi]; ++h) mixed = mixed || s.body[up_spring[h]] != static_cast<int>(b);
    if (up_start[hi] > up_start[lo]) runs.push_back({up_start[lo], up_start[hi], static_cast<int>(b)});
  }
  long long covered = 0;
  for (const Run& r : runs) covered += r.end - r.begin;
  mixed = mixed || covered != static_cast<long long>(U);  // springs on nodes of no body
}

double* SpringGather::box(std::vector<double>& b) {
  const auto a = reinterpret_cast<std::uintptr_t>(b.data());
  return b.data() + ((32 - a % 32) % 32) / sizeof(double);
}

namespace {

// Node bounds of T parts of about equal cost(n) (cost: a node's prefix of work, nondecreasing).
template <class Cost>
std::vector<int> balanced_bounds(int n, int T, Cost&& cost) {
  std::vector<int> bounds(static_cast<std::size_t>(T) + 1, n);
  bounds[0] = 0;
  for (int q = 1; q < T; ++q) {
    const long long target = cost(n) * q / T;
    int lo = 0, hi = n;  // first node whose prefix cost reaches the target
    while (lo < hi) {
      const int mid = (lo + hi) / 2;
      if (cost(mid) < target) lo = mid + 1;
      else hi = mid;
    }
    bounds[q] = std::max(lo, bounds[q - 1]);
  }
  return bounds;
}

}  // namespace

const SpringGather::Split& SpringGather::split(int T) {
  for (const Split& sp : splits)
    if (sp.T == T) return sp;
  Split sp;
  sp.T = T;
  const int n = nodes;
  sp.bounds = balanced_bounds(n, T, [&](int i) { return kUpWeight * up_start[i] + lo_start[i]; });
  // The halo's springs, part by part: (upper half-edge, lower half-edge) in upper order.
  std::vector<std::vector<std::pair<int, int>>> copies(static_cast<std::size_t>(T));
  std::size_t total = 0;
  for (int t = 0; t < T; ++t) {
    const int i0 = sp.bounds[t], i1 = sp.bounds[t + 1];
    for (int l = lo_start[i0]; l < lo_start[i1]; ++l)
      if (up_self[lo_slot[l]] < i0) copies[t].emplace_back(lo_slot[l], l);
    std::sort(copies[t].begin(), copies[t].end());  // runs of one body
    total += copies[t].size();
  }
  if (static_cast<double>(total) > kHaloShare * static_cast<double>(springs)) {
    sp.two_phase = true;
    sp.bounds = balanced_bounds(n, T, [&](int i) { return static_cast<long long>(up_start[i]) + lo_start[i]; });
    splits.push_back(std::move(sp));
    return splits.back();
  }
  // The halo, appended in place of the arrays' trailing padding, which follows it.
  const std::size_t end = up_self.size() - kPad;
  for (auto* a : {&up_self, &up_other, &up_spring}) a->resize(end);
  for (auto* a : {&up_rest, &up_inv_rest, &up_stiff}) a->resize(end);
  sp.lo_slot = lo_slot;
  sp.halo_start.push_back(0);
  for (int t = 0; t < T; ++t) {
    for (const auto& [h, l] : copies[t]) {
      const int c = static_cast<int>(up_self.size());
      up_self.push_back(up_self[h]), up_other.push_back(up_other[h]), up_spring.push_back(up_spring[h]);
      up_rest.push_back(up_rest[h]), up_inv_rest.push_back(up_inv_rest[h]), up_stiff.push_back(up_stiff[h]);
      sp.lo_slot[l] = c;
      int body = -1;  // the body of the run holding h (none in a mixed world: laws per spring)
      for (const Run& r : runs)
        if (r.begin <= h && h < r.end) body = r.body;
      if (sp.halo.size() > static_cast<std::size_t>(sp.halo_start.back()) && sp.halo.back().body == body &&
          sp.halo.back().end == c)
        ++sp.halo.back().end;
      else
        sp.halo.push_back({c, c + 1, body});
    }
    sp.halo_start.push_back(static_cast<int>(sp.halo.size()));
  }
  const std::size_t size = up_self.size() + kPad;
  up_self.resize(size, 0), up_other.resize(size, 0), up_spring.resize(size, 0);
  up_rest.resize(size, 1.0), up_inv_rest.resize(size, 1.0), up_stiff.resize(size, 0.0);
  F.assign(4 * size + 4, 0.0), G.assign(4 * size + 4, 0.0), R.assign(4 * size + 4, 0.0);
  e.assign(size, 0.0);
  splits.push_back(std::move(sp));
  return splits.back();
}

namespace {

const double* coords(const Points& p) { return p.empty() ? nullptr : p[0].data(); }
double* coords(Points* p) { return p && !p->empty() ? (*p)[0].data() : nullptr; }

// The tangent stiffness over l2 of the evaluation half (kernels.inl law_lanes), one spring.
double tangent_over_l2(const SpringLaw& law, double L0, double l) {
  const double s = l - L0, r = 1.0 / l, q = 1.0 / L0;
  switch (law.kind) {
    case SpringLawKind::linear: return std::fabs(law.k) * r * r;
    case SpringLawKind::cubic: return std::fabs(cubic_tangent(law.k, law.beta, L0, s, q, 3.0)) * (r * r);
    case SpringLawKind::exponential: {
      const double x = law.beta * (s * q);
      return std::fabs(law.k * (1.0 + spring_expm1(x))) * r * r;
    }
  }
  return 0.0;
}

// The evaluation half of a world with springs across bodies (hand-built worlds): the kernels'
// numbers one half-edge at a time, each spring with its own body's law and dashpot.
void mixed_eval(SpringGather& g, const World& w, bool springs, bool dashpots, bool rows, bool energy, int h0, int h1) {
  const Springs& S = w.springs;
  for (int h = h0; h < h1; ++h) {
    const int k = g.up_spring[h];
    const Vec3 xi = w.x[g.up_self[h]], xj = w.x[g.up_other[h]];
    const double d[3] = {xj[0] - xi[0], xj[1] - xi[1], xj[2] - xi[2]};
    const double l2 = (d[0] * d[0] + d[1] * d[1]) + d[2] * d[2];
    const double l = std::sqrt(l2);
    const SpringLaw law = w.body_law[S.body[k]].with(S.k[k]);
    const double L0 = S.rest[k];
    const bool zero = l2 <= 0.0;
    if (springs) {
      const double c = spring_force_per_length(law, L0, l);
      double* q = SpringGather::box(g.F) + 4 * static_cast<std::size_t>(h);
      for (int a = 0; a < 3; ++a) q[a] = zero ? 0.0 : c * d[a];
      q[3] = 0.0;
    }
    if (rows) {
      const double t = tangent_over_l2(law, L0, l);
      const double ax = std::fabs(d[0]), ay = std::fabs(d[1]), az = std::fabs(d[2]);
      const double rr = 2.0 * t * ((ax + ay) + az);
      const double ad[3] = {ax, ay, az};
      double* q = SpringGather::box(g.R) + 4 * static_cast<std::size_t>(h);
      for (int a = 0; a < 3; ++a) q[a] = 0.0 < l2 ? rr * ad[a] : 0.0;
      q[3] = 0.0;
    }
    if (energy) g.e[h] = spring_energy(law, L0, l);
    if (dashpots) {
      const Vec3 vi = w.v[g.up_self[h]], vj = w.v[g.up_other[h]];
      const double u[3] = {vj[0] - vi[0], vj[1] - vi[1], vj[2] - vi[2]};
      const double r = 1.0 / l;
      const double s = w.bodies[S.body[k]].material.damping * ((u[0] * d[0] + u[1] * d[1]) + u[2] * d[2]) * (r * r);
      double* q = SpringGather::box(g.G) + 4 * static_cast<std::size_t>(h);
      for (int a = 0; a < 3; ++a) q[a] = zero ? 0.0 : s * d[a];
      q[3] = 0.0;
    }
  }
}

}  // namespace

namespace {

// One force pass's set-up (the kernels' runs over the gather's arrays and the outputs) and its
// pieces: the evaluation of a range of upper half-edges, the sums of a range of nodes.
class Pass {
 public:
  // `lo_slot`: the lower half-edges' slots the sums read (a halo split's redirected ones).
  Pass(SpringGather& g, const World& w, bool springs, bool dashpots, const SpringPassOut& out, const int* lo_slot)
      : g_(g), w_(w), kern_(simd::kernels()) {
    springs_ = springs && out.f;
    dashpots_ = dashpots && out.f;
    rows_ = out.rows != nullptr, energy_ = out.energy != nullptr;
    ev_.self = g.up_self.data(), ev_.other = g.up_other.data(), ev_.rest = g.up_rest.data();
    ev_.inv_rest = g.up_inv_rest.data(), ev_.stiff = g.up_stiff.data();
    ev_.x = coords(w.x), ev_.v = coords(w.v);
    ev_.F = springs_ ? SpringGather::box(g.F) : nullptr;
    ev_.G = dashpots_ ? SpringGather::box(g.G) : nullptr;
    ev_.R = rows_ ? SpringGather::box(g.R) : nullptr;
    ev_.e = energy_ ? g.e.data() : nullptr;
    su_.up_start = g.up_start.data(), su_.lo_start = g.lo_start.data();
    su_.lo_slot = lo_slot;
    su_.F = ev_.F, su_.G = ev_.G, su_.R = ev_.R;
    su_.e = ev_.e;
    su_.f = coords(out.f);
    su_.f_spring = coords(out.f_spring), su_.f_dashpot = coords(out.f_dashpot);
    su_.energy = energy_ ? out.energy->data() : nullptr;
    su_.rows = rows_ ? (*out.rows)[0].data() : nullptr;
  }

  // The upper half-edges [h0, h1) of one body (none: a mixed world's, spring by spring).
  void eval_run(int h0, int h1, int body) const {
    if (g_.mixed || body < 0) return mixed_eval(g_, w_, springs_, dashpots_, rows_, energy_, h0, h1);
    simd::SpringEvalRun r = ev_;
    const BodyLaw& law = w_.body_law[body];
    r.beta = law.beta;
    r.damping = w_.bodies[body].material.damping;
    r.h0 = h0, r.h1 = h1;
    switch (law.kind) {
      case SpringLawKind::linear: kern_.spring_eval_linear(r); break;
      case SpringLawKind::cubic: kern_.spring_eval_cubic(r); break;
      case SpringLawKind::exponential: kern_.spring_eval_exponential(r); break;
    }
  }
  // Every upper half-edge of [h0, h1) (body by body).
  void eval(int h0, int h1) const {
    if (g_.mixed) return mixed_eval(g_, w_, springs_, dashpots_, rows_, energy_, h0, h1);
    for (const SpringGather::Run& run : g_.runs) {
      const int a = std::max(h0, run.begin), b = std::min(h1, run.end);
      if (a < b) eval_run(a, b, run.body);
    }
  }
  // The sums of the nodes [i0, i1) (every half-edge they read evaluated already).
  void sum(int i0, int i1) const {
    simd::SpringSumRun r = su_;
    r.i0 = i0, r.i1 = i1;
    kern_.spring_sum(r);
  }
  // The nodes [i0, i1) of a part, in blocks of kBlock nodes: their springs evaluated, then their
  // nodes summed while the box entries are still in cache (a lower half-edge's upper end is an
  // earlier node: of this block, of an earlier one or of the part's halo, evaluated already).
  void part(int i0, int i1) const {
    for (int b0 = i0; b0 < i1; b0 += kBlock) {
      const int b1 = std::min(i1, b0 + kBlock);
      eval(g_.up_start[b0], g_.up_start[b1]);
      sum(b0, b1);
    }
  }

 private:
  SpringGather& g_;
  const World& w_;
  const simd::Kernels& kern_;
  bool springs_ = false, dashpots_ = false, rows_ = false, energy_ = false;
  simd::SpringEvalRun ev_{};
  simd::SpringSumRun su_{};
};

}  // namespace

void spring_pass(SpringGather& g, const World& w, bool springs, bool dashpots, const SpringPassOut& out) {
  if (!g.matches(w)) g.build(w);
  const int U = g.up_start[g.nodes];
  const std::size_t half_edges = static_cast<std::size_t>(U) + g.lo_start[g.nodes];
  const int T = threads_for(half_edges, kHalfEdgesPerThread);
  // (before any pointer into the arrays is taken: a new split grows them)
  const SpringGather::Split* split = T > 1 ? &g.split(T) : nullptr;
  const Pass pass(g, w, springs, dashpots, out,
                  split && !split->two_phase ? split->lo_slot.data() : g.lo_slot.data());
  if (!split) return pass.part(0, g.nodes);
  if (split->two_phase) {  // equal ranges of upper half-edges, then equal ranges of nodes
    // Each thread takes every k-th part from its own (the team may be smaller than T).
#pragma omp parallel num_threads(T)
    {
      int me = 0, k = 1;
#ifdef _OPENMP
      me = omp_get_thread_num(), k = omp_get_num_threads();
#endif
      for (int t = me; t < T; t += k) {
        std::size_t h0, h1;
        split_range(static_cast<std::size_t>(U), T, t, h0, h1);
        pass.eval(static_cast<int>(h0), static_cast<int>(h1));
      }
#pragma omp barrier
      for (int t = me; t < T; t += k) pass.sum(split->bounds[t], split->bounds[t + 1]);
    }
    return;
  }
  // One part per thread, each with its halo first; the numbers do not depend on the partition.
#pragma omp parallel for num_threads(T) schedule(static, 1)
  for (int t = 0; t < T; ++t) {
    for (int q = split->halo_start[t]; q < split->halo_start[t + 1]; ++q) {
      const SpringGather::Run& run = split->halo[q];
      pass.eval_run(run.begin, run.end, run.body);
    }
    pass.part(split->bounds[t], split->bounds[t + 1]);
  }
}

bool spring_pass_shareable(SpringGather& g, const World& w) {
  if (!g.matches(w)) g.build(w);
  const std::size_t half_edges = static_cast<std::size_t>(g.up_start[g.nodes]) + g.lo_start[g.nodes];
  if (threads_for(half_edges, kHalfEdgesPerThread) < 2) return false;
  if (g.chunk_bounds.empty())
    g.chunk_bounds = balanced_bounds(g.nodes, SpringGather::kChunks,
                                     [&](int i) { return static_cast<long long>(g.up_start[i]) + g.lo_start[i]; });
  for (auto& f : g.claims->free) f.store(static_cast<std::uint64_t>(SpringGather::kChunks) << 32);
  return true;
}

void spring_pass_shared(SpringGather& g, const World& w, bool springs, bool dashpots, const SpringPassOut& out) {
  const Pass pass(g, w, springs, dashpots, out, g.lo_slot.data());
  int me = 0;
#ifdef _OPENMP
  me = omp_get_thread_num();
#endif
  SpringGather::Claims& cl = *g.claims;
  // Claims the next free chunk at this thread's end (one compare-and-swap of both ends): every
  // chunk exactly once; false when none is left.
  auto claim = [&](int phase, int& c) {
    std::atomic<std::uint64_t>& f = cl.free[phase];
    std::uint64_t v = f.load();
    for (;;) {
      const std::uint32_t lo = static_cast<std::uint32_t>(v), hi = static_cast<std::uint32_t>(v >> 32);
      if (lo >= hi) return false;
      const bool front = me % 2 == 0;
      const std::uint64_t next = front ? (v + 1) : (static_cast<std::uint64_t>(hi - 1) << 32 | lo);
      if (f.compare_exchange_weak(v, next)) {
        c = static_cast<int>(front ? lo : hi - 1);
        return true;
      }
    }
  };
  for (int c; claim(0, c);) pass.eval(g.up_start[g.chunk_bounds[c]], g.up_start[g.chunk_bounds[c + 1]]);
#pragma omp barrier
  for (int c; claim(1, c);) pass.sum(g.chunk_bounds[c], g.chunk_bounds[c + 1]);
#pragma omp barrier
}

double sum_node_energy(const std::vector<double>& e) {
  constexpr std::size_t kChunk = 4096;
  const std::size_t n = e.size(), chunks = (n + kChunk - 1) / kChunk;
  double total = 0.0;
  for (std::size_t c = 0; c < chunks; ++c) {
    double part = 0.0;
    for (std::size_t k = c * kChunk; k < std::min(n, (c + 1) * kChunk); ++k) part += e[k];
    total += part;
  }
  return total;
}

void add_mass_damping(const World& w, Points& f) {
  for (const Body& b : w.bodies) {
    const double a = b.material.mass_damping;
    if (a == 0.0) continue;
    const int T = threads_for(static_cast<std::size_t>(b.size()), 32768);
#pragma omp parallel for num_threads(T) if(T > 1) schedule(static)
    for (int i = b.begin; i < b.end; ++i) f[i] -= (a * w.m[i]) * w.v[i];
  }
}

void add_spring_forces(SpringGather& g, const World& w, Points& f) {
  SpringPassOut o;
  o.f = &f;
  spring_pass(g, w, true, false, o);
}

void add_damping_forces(SpringGather& g, const World& w, Points& f) {
  SpringPassOut o;
  o.f = &f;
  spring_pass(g, w, false, true, o);
  add_mass_damping(w, f);
}

void add_spring_forces(const World& w, Points& f) {
  SpringGather g;
  add_spring_forces(g, w, f);
}

void add_damping_forces(const World& w, Points& f) {
  SpringGather g;
  add_damping_forces(g, w, f);
}

double spring_potential(SpringGather& g, const World& w, std::vector<double>& e) {
  e.assign(static_cast<std::size_t>(w.num_nodes()), 0.0);
  SpringPassOut o;
  o.energy = &e;
  spring_pass(g, w, false, false, o);
  return sum_node_energy(e);
}

double spring_potential(const World& w) {
  SpringGather g;
  std::vector<double> e;
  return spring_potential(g, w, e);
}

void add_spring_stiffness_rows(SpringGather& g, const World& w, std::vector<Vec3>& rows) {
  SpringPassOut o;
  o.rows = &rows;
  spring_pass(g, w, false, false, o);
}

void add_spring_stiffness_rows(const World& w, std::vector<Vec3>& rows) {
  SpringGather g;
  add_spring_stiffness_rows(g, w, rows);
}

}  // namespace harness
