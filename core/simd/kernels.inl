// The bodies of the SIMD kernels (kernels.hpp), each written once as a template over the lane
// types of lanes.inl. Included once per instruction set by kernels_<isa>.cpp, which defines
// HARNESS_SIMD_NS and is compiled with that set's flags; nothing else includes it.
#include "core/simd/kernels.hpp"
#include "core/springs.hpp"


#ifndef HARNESS_SIMD_NS
#error "kernels_<isa>.cpp defines HARNESS_SIMD_NS before including kernels.inl"
#endif

#include "core/simd/lanes.inl"

namespace harness::simd::HARNESS_SIMD_NS {
namespace {

// ---- Voxel indices (VoxelIndexer).
// W points per iteration, as VoxelIndexer's scalar operator: t = (p - c) * inv per axis (1/v is
// a power of two: the product is the quotient), the range test lo <= t < hi in double (which
// rejects NaN, and anything beyond int range before any conversion), then the index in double,
// floor(t) - lo weighted by 1, dims.x, dims.x dims.y and summed (integers below 2^31: exact),
// -1 for the points outside, converted to int.
template <class D>
std::size_t voxel_cells_lanes(const VoxelGrid& g, const double* q, std::size_t n, int* out) {
  constexpr int W = D::W;
  const D c0 = D::set1(g.c[0]), c1 = D::set1(g.c[1]), c2 = D::set1(g.c[2]), inv = D::set1(g.inv);
  const D lo0 = D::set1(g.lo[0]), lo1 = D::set1(g.lo[1]), lo2 = D::set1(g.lo[2]);
  const D hi0 = D::set1(g.hi[0]), hi1 = D::set1(g.hi[1]), hi2 = D::set1(g.hi[2]);
  const D dx = D::set1(g.dx), dxy = D::set1(g.dxy), none = D::set1(-1.0);
  std::size_t k = 0;
  for (; k + W <= n; k += W, q += 3 * W) {
    D px, py, pz;
    D::load_xyz(q, px, py, pz);
    const D t0 = (px - c0) * inv, t1 = (py - c1) * inv, t2 = (pz - c2) * inv;
    const auto in = ((ge(t0, lo0) & lt(t0, hi0)) & (ge(t1, lo1) & lt(t1, hi1))) & (ge(t2, lo2) & lt(t2, hi2));
    const D lin = ((floor(t0) - lo0) + dx * (floor(t1) - lo1)) + dxy * (floor(t2) - lo2);
    store_i32(out + k, select(in, lin, none));
  }
  return k;
}

template <class D>
void voxel_cells(const VoxelGrid& g, const double* xyz, std::size_t n, int* out) {
  const std::size_t k = voxel_cells_lanes<D>(g, xyz, n, out);
  if constexpr (D::W > 1) voxel_cells_lanes<D1>(g, xyz + 3 * k, n - k, out + k);
}

// ---- Bounding box (points_bounds).
// W points (three loads) per iteration, one accumulator per load position; at the end lane j of
// the 3W is folded into coordinate j % 3. (Each load's min and max follow it: GCC 12 reloads
// the data when all loads come first.) min(p, l) and max(p, h) are the scalar rule, NaN
// included, so only the sign of a zero bound depends on the grouping.
template <class D>
std::size_t bounds_lanes(const double* q, std::size_t n, double* r) {
  constexpr int W = D::W;
  const D inf = D::set1(__builtin_inf()), ninf = D::set1(-__builtin_inf());
  D la = inf, lb = inf, lc = inf, ha = ninf, hb = ninf, hc = ninf;
  std::size_t k = 0;
  for (; k + W <= n; k += W, q += 3 * W) {
    const D a = D::load(q);
    la = min(a, la), ha = max(a, ha);
    const D b = D::load(q + W);
    lb = min(b, lb), hb = max(b, hb);
    const D c = D::load(q + 2 * W);
    lc = min(c, lc), hc = max(c, hc);
  }
  double L[3 * W], H[3 * W];
  store(L, la), store(L + W, lb), store(L + 2 * W, lc);
  store(H, ha), store(H + W, hb), store(H + 2 * W, hc);
  for (int j = 0; j < 3 * W; j += 3)
    for (int a = 0; a < 3; ++a) {
      r[a] = L[j + a] < r[a] ? L[j + a] : r[a];
      r[3 + a] = r[3 + a] < H[j + a] ? H[j + a] : r[3 + a];
    }
  return k;
}

template <class D>
void bounds(const double* xyz, std::size_t n, double* lohi) {
  const std::size_t k = bounds_lanes<D>(xyz, n, lohi);
  if constexpr (D::W > 1) bounds_lanes<D1>(xyz + 3 * k, n - k, lohi);
}

// ---- Smallest (as unsigned) and largest voxel of a chunk of nodes (VoxelData::prepare).
template <class I>
std::size_t cell_range_lanes(const int* c, std::size_t n, unsigned& lo, int& hi) {
  constexpr int W = I::W;
  I l = I::set1(-1), h = I::set1(-1);
  std::size_t k = 0;
  for (; k + W <= n; k += W) {
    const I v = I::load(c + k);
    l = min_u(l, v), h = max_s(h, v);
  }
  int L[W], H[W];
  store(L, l), store(H, h);
  for (int j = 0; j < W; ++j) {
    const unsigned u = static_cast<unsigned>(L[j]);
    lo = u < lo ? u : lo;
    hi = H[j] > hi ? H[j] : hi;
  }
  return k;
}

template <class I>
void cell_range(const int* c, std::size_t n, unsigned& lo, int& hi) {
  lo = ~0u, hi = -1;
  const std::size_t k = cell_range_lanes<I>(c, n, lo, hi);
  if constexpr (I::W > 1) cell_range_lanes<I1>(c + k, n - k, lo, hi);
}

// ---- The force pass (SpringEvalRun, SpringSumRun: kernels.hpp).
// The sums use four-lane registers (D4) at every SIMD level, one lane (D1) at the scalar level,
// the same partial sums in the same order at every level (sum_nodes below).

// The laws' constants as lanes, made once per call.
template <class D>
struct LawConstants {
  D zero, half, quarter, one, two, three, six, c24, c120, eighth, tiny_x, small_x, direct, beta, inv_beta, damping;
  D coef[12];
  LawConstants(double beta_, double damping_) {
    zero = D::set1(0.0), half = D::set1(0.5), quarter = D::set1(0.25), one = D::set1(1.0), two = D::set1(2.0);
    three = D::set1(3.0), six = D::set1(6.0), c24 = D::set1(24.0), c120 = D::set1(120.0), eighth = D::set1(0.125);
    tiny_x = D::set1(1e-8), small_x = D::set1(1e-3), direct = D::set1(kExpm1Direct);
    beta = D::set1(beta_), inv_beta = D::set1(1.0 / beta_), damping = D::set1(damping_);
    for (int k = 0; k < 12; ++k) coef[k] = D::set1(kExpm1Coef[k]);
  }
};

// The exponential law's expm1(x) (springs.hpp's spring_expm1): the polynomial, or libm lane by
// lane beyond its range (or NaN).
template <class D>
[[gnu::always_inline]] inline D expm1_lanes(const LawConstants<D>& C, const D& x) {
  D em1 = expm1_halving(x, C.coef, C.eighth, C.two);
  const unsigned in = bits(le(abs(x), C.direct));
  if (in != (1u << D::W) - 1u) {
    double xs[D::W], es[D::W];
    store(xs, x), store(es, em1);
    for (int j = 0; j < D::W; ++j)
      if (!((in >> j) & 1u)) es[j] = __builtin_expm1(xs[j]);
    em1 = D::load(es);
  }
  return em1;
}

// The law at the lanes' lengths (springs.hpp, each expression as the scalar one): c the tension
// over length, t the tangent stiffness over l2 (want_t), e the energy (want_e), from s = l - L0,
// r = 1 / l and q = 1 / L0. What is not wanted is not computed. em1_given: the exponential law's
// expm1(beta ((l - L0) q)) computed already (expm1_lanes), or null.
template <class D, SpringLawKind K>
[[gnu::always_inline]] inline void law_lanes(const LawConstants<D>& C, const D& k, const D& L0, const D& q,
                                             const D& l, const D& r, bool want_t, bool want_e, D& c, D& t,
                                             D& e, const D* em1_given = nullptr) {
  const D s = l - L0;
  if constexpr (K == SpringLawKind::linear) {
    c = linear_law(k, s, r);
    if (want_t) t = abs(k) * r * r;
    if (want_e) e = linear_energy(k * L0 * L0, s * q, C.half);
  } else if constexpr (K == SpringLawKind::cubic) {
    c = cubic_law(k, C.beta, L0, s, q, r);
    if (want_t) t = abs(cubic_tangent(k, C.beta, L0, s, q, C.three)) * (r * r);
    if (want_e) e = cubic_energy(k * L0 * L0, C.beta, s * q, C.half, C.quarter);
  } else {
    const D eps = s * q;
    const D x = C.beta * eps;
    const D em1 = em1_given ? *em1_given : expm1_lanes(C, x);
    c = select(lt(abs(x), C.tiny_x), exponential_near(k, s, x, C.one, C.half, r),
               exponential_far(k, L0, em1, C.inv_beta, r));
    if (want_t) t = abs(k * (C.one + em1)) * r * r;
    if (want_e) {
      const D g = select(lt(abs(x), C.small_x), exp_energy_series(x, C.half, C.six, C.c24, C.c120),
                         exp_energy_direct(x, em1));
      e = k * L0 * L0 * eps * eps * g;
    }
  }
}

// ---- The evaluation half (SpringEvalRun): W upper half-edges per iteration, the last ones (all
// of them at the scalar level) one at a time with the one-lane type: every lane does the same
// operations, so the box holds the same numbers at every level.
template <class D, SpringLawKind K, bool SP, bool RO, bool EN, bool DP>
[[gnu::always_inline]] inline void eval_lanes(const SpringEvalRun& r, const LawConstants<D>& C, int h) {
  typename D::P d;  // the springs' d = x_j - x_i, each lane's as a point (the boxes' layout)
  D dx, dy, dz;
  D::gather_diff(r.x, r.self + h, r.other + h, d, dx, dy, dz);
  const D l2 = (dx * dx + dy * dy) + dz * dz;
  const auto zero_length = le(l2, C.zero);  // l <= 0 exactly when l2 <= 0 (NaN: neither)
  const D l = sqrt(l2);
  const D rl = C.one / l;  // the pass's one division: 1 / l
  const std::ptrdiff_t q = 4 * static_cast<std::ptrdiff_t>(h);  // the boxes' entry: four doubles
  if constexpr (SP || RO || EN) {
    D c = C.zero, t = C.zero, e = C.zero;
    law_lanes<D, K>(C, D::load(r.stiff + h), D::load(r.rest + h), D::load(r.inv_rest + h), l, rl, RO, EN, c, t, e);
    // F = c d, 0 for a spring of zero length: there d is (+-0 or below 1e-154 in each component), so
    // 0 d is +-0, which a sum adds as nothing (kernels.hpp), as it does the 0 it stands for.
    if constexpr (SP) store_points(r.F + q, d, select(zero_length, C.zero, c));
    if constexpr (RO) store_points_abs(r.R + q, d, C.two * t * ((abs(dx) + abs(dy)) + abs(dz)), lt(C.zero, l2));
    if constexpr (EN) store(r.e + h, e);
  }
  if constexpr (DP) {
    typename D::P du;
    D ux, uy, uz;
    D::gather_diff(r.v, r.self + h, r.other + h, du, ux, uy, uz);
    const D s = C.damping * ((ux * dx + uy * dy) + uz * dz) * (rl * rl);
    store_points(r.G + q, d, select(zero_length, C.zero, s));
  }
}

// The same numbers for kV vectors of W half-edges at a time, in two loops: first every vector's
// gathers, length, square root and division (its d kept as loaded), then every vector's law and
// stores. A vector's whole chain (gathers, square root, division, the exponential law's expm1) is
// longer than the processor's window holds of a loop that does it all at once; split, each loop's
// iterations are short and independent, and several overlap. Each lane's operations are
// eval_lanes's, in its order.
template <class D>
struct EvalBlock {
  static constexpr int kV = 16;
  typename D::P d[kV];
  D l2[kV], l[kV], rl[kV], sa[kV], ud[kV], em1[kV];
};

template <class D, SpringLawKind K, bool SP, bool RO, bool EN, bool DP>
[[gnu::always_inline]] inline void eval_block(const SpringEvalRun& r, const LawConstants<D>& C, int h,
                                              EvalBlock<D>& b) {
  constexpr int V = EvalBlock<D>::kV, W = D::W;
  for (int k = 0; k < V; ++k) {
    const int hk = h + k * W;
    D dx, dy, dz;
    D::gather_diff(r.x, r.self + hk, r.other + hk, b.d[k], dx, dy, dz);
    const D l2 = (dx * dx + dy * dy) + dz * dz;
    const D l = sqrt(l2);
    b.l2[k] = l2, b.l[k] = l, b.rl[k] = C.one / l;
    if constexpr (RO) b.sa[k] = (abs(dx) + abs(dy)) + abs(dz);
    if constexpr (DP) {
      typename D::P du;
      D ux, uy, uz;
      D::gather_diff(r.v, r.self + hk, r.other + hk, du, ux, uy, uz);
      b.ud[k] = (ux * dx + uy * dy) + uz * dz;
    }
  }
  if constexpr (K == SpringLawKind::exponential && (SP || RO || EN))
    for (int k = 0; k < V; ++k) {  // expm1's chain on its own (law_lanes's x, the same operations)
      const int hk = h + k * W;
      b.em1[k] = expm1_lanes(C, C.beta * ((b.l[k] - D::load(r.rest + hk)) * D::load(r.inv_rest + hk)));
    }
  for (int k = 0; k < V; ++k) {
    const int hk = h + k * W;
    const std::ptrdiff_t q = 4 * static_cast<std::ptrdiff_t>(hk);
    const auto zero_length = le(b.l2[k], C.zero);
    const D rl = b.rl[k];
    if constexpr (SP || RO || EN) {
      D c = C.zero, t = C.zero, e = C.zero;
      law_lanes<D, K>(C, D::load(r.stiff + hk), D::load(r.rest + hk), D::load(r.inv_rest + hk), b.l[k], rl, RO, EN, c,
                      t, e, K == SpringLawKind::exponential ? &b.em1[k] : nullptr);
      if constexpr (SP) store_points(r.F + q, b.d[k], select(zero_length, C.zero, c));
      if constexpr (RO) store_points_abs(r.R + q, b.d[k], C.two * t * b.sa[k], lt(C.zero, b.l2[k]));
      if constexpr (EN) store(r.e + hk, e);
    }
    if constexpr (DP) {
      const D s = C.damping * b.ud[k] * (rl * rl);
      store_points(r.G + q, b.d[k], select(zero_length, C.zero, s));
    }
  }
}

// One variant per combination of outputs (springs, rows, energy, dashpots): what a pass does not
// want is compiled out, and no flag is tested per iteration.
template <class D, SpringLawKind K, bool SP, bool RO, bool EN, bool DP>
void spring_eval_variant(const SpringEvalRun& r) {
  int h = r.h0;
  if constexpr (D::W > 1) {
    const LawConstants<D> C(r.beta, r.damping);
    if constexpr (K == SpringLawKind::exponential) {
      EvalBlock<D> b;
      for (; h + EvalBlock<D>::kV * D::W <= r.h1; h += EvalBlock<D>::kV * D::W) eval_block<D, K, SP, RO, EN, DP>(r, C, h, b);
    }
    for (; h + D::W <= r.h1; h += D::W) eval_lanes<D, K, SP, RO, EN, DP>(r, C, h);
  }
  const LawConstants<D1> C1(r.beta, r.damping);
  for (; h < r.h1; ++h) eval_lanes<D1, K, SP, RO, EN, DP>(r, C1, h);
}

template <class D, SpringLawKind K>
void spring_eval(const SpringEvalRun& r) {
  const int key = (r.F ? 8 : 0) | (r.R ? 4 : 0) | (r.e ? 2 : 0) | (r.G ? 1 : 0);
  switch (key) {
    case 0: return;
    case 1: return spring_eval_variant<D, K, false, false, false, true>(r);
    case 2: return spring_eval_variant<D, K, false, false, true, false>(r);
    case 3: return spring_eval_variant<D, K, false, false, true, true>(r);
    case 4: return spring_eval_variant<D, K, false, true, false, false>(r);
    case 5: return spring_eval_variant<D, K, false, true, false, true>(r);
    case 6: return spring_eval_variant<D, K, false, true, true, false>(r);
    case 7: return spring_eval_variant<D, K, false, true, true, true>(r);
    case 8: return spring_eval_variant<D, K, true, false, false, false>(r);
    case 9: return spring_eval_variant<D, K, true, false, false, true>(r);
    case 10: return spring_eval_variant<D, K, true, false, true, false>(r);
    case 11: return spring_eval_variant<D, K, true, false, true, true>(r);
    case 12: return spring_eval_variant<D, K, true, true, false, false>(r);
    case 13: return spring_eval_variant<D, K, true, true, false, true>(r);
    case 14: return spring_eval_variant<D, K, true, true, true, false>(r);
    default: return spring_eval_variant<D, K, true, true, true, true>(r);
  }
}

// ---- The summing half (SpringSumRun). The four-lane levels keep a node's partial sum q of each
// quantity as one four-lane register (x y z and a fourth lane never read): half-edge q of a list
// adds its box entry, loaded as four doubles, to register q % 4 (four at a time, then the last
// one to three into registers 0, 1, 2), for the upper list then the lower one; the node's sum is
// (p0 + p1) + (p2 + p3), lane by lane. The scalar level does the same one component at a time.
// Both are the partial sums of kernels.hpp, in its order. What a pass does not want (springs,
// dashpots, rows, energy) is compiled out (one variant per combination).

// One half-edge's entry of the box B (x y z 0 at 4 k) as four lanes.
template <class D>
[[gnu::always_inline]] inline D entry(const double* B, int k) {
  return D::load(B + 4 * static_cast<std::ptrdiff_t>(k));
}

// The node's four partials of a quantity in registers (four lanes).
template <class D>
struct Partials {
  D p0, p1, p2, p3;
  explicit Partials(D z) : p0(z), p1(z), p2(z), p3(z) {}
  D sum() const { return (p0 + p1) + (p2 + p3); }
};

template <class D, bool SP, bool DP, bool RO>
[[gnu::always_inline]] inline void add_upper(const SpringSumRun& r, int h, int n, Partials<D>& a, Partials<D>& b,
                                             Partials<D>& c) {
  // n in 1..4 half-edges h, h + 1, ...: into partials 0, 1, ..., n - 1.
  if constexpr (SP) {
    a.p0 = a.p0 + entry<D>(r.F, h);
    if (n > 1) a.p1 = a.p1 + entry<D>(r.F, h + 1);
    if (n > 2) a.p2 = a.p2 + entry<D>(r.F, h + 2);
    if (n > 3) a.p3 = a.p3 + entry<D>(r.F, h + 3);
  }
  if constexpr (DP) {
    b.p0 = b.p0 + entry<D>(r.G, h);
    if (n > 1) b.p1 = b.p1 + entry<D>(r.G, h + 1);
    if (n > 2) b.p2 = b.p2 + entry<D>(r.G, h + 2);
    if (n > 3) b.p3 = b.p3 + entry<D>(r.G, h + 3);
  }
  if constexpr (RO) {
    c.p0 = c.p0 + entry<D>(r.R, h);
    if (n > 1) c.p1 = c.p1 + entry<D>(r.R, h + 1);
    if (n > 2) c.p2 = c.p2 + entry<D>(r.R, h + 2);
    if (n > 3) c.p3 = c.p3 + entry<D>(r.R, h + 3);
  }
}

template <class D, bool SP, bool DP, bool RO>
[[gnu::always_inline]] inline void add_lower(const SpringSumRun& r, const int* slot, int n, Partials<D>& a,
                                             Partials<D>& b, Partials<D>& c) {
  // n in 1..4 lower half-edges (their upper entries slot[0], slot[1], ...): -F, -G, +R. p - F is
  // p + (0 - F) of kernels.hpp bit for bit: a partial sum is never -0 (it starts at +0).
  const int k0 = slot[0], k1 = n > 1 ? slot[1] : 0, k2 = n > 2 ? slot[2] : 0, k3 = n > 3 ? slot[3] : 0;
  if constexpr (SP) {
    a.p0 = a.p0 - entry<D>(r.F, k0);
    if (n > 1) a.p1 = a.p1 - entry<D>(r.F, k1);
    if (n > 2) a.p2 = a.p2 - entry<D>(r.F, k2);
    if (n > 3) a.p3 = a.p3 - entry<D>(r.F, k3);
  }
  if constexpr (DP) {
    b.p0 = b.p0 - entry<D>(r.G, k0);
    if (n > 1) b.p1 = b.p1 - entry<D>(r.G, k1);
    if (n > 2) b.p2 = b.p2 - entry<D>(r.G, k2);
    if (n > 3) b.p3 = b.p3 - entry<D>(r.G, k3);
  }
  if constexpr (RO) {
    c.p0 = c.p0 + entry<D>(r.R, k0);
    if (n > 1) c.p1 = c.p1 + entry<D>(r.R, k1);
    if (n > 2) c.p2 = c.p2 + entry<D>(r.R, k2);
    if (n > 3) c.p3 = c.p3 + entry<D>(r.R, k3);
  }
}

template <class D, bool SP, bool DP, bool RO, bool EN>
void sum_nodes(const SpringSumRun& r) {
  for (int i = r.i0; i < r.i1; ++i) {
    const std::ptrdiff_t node = i;
    double se[4] = {0.0, 0.0, 0.0, 0.0}, sd[4] = {0.0, 0.0, 0.0, 0.0}, sr[4] = {0.0, 0.0, 0.0, 0.0};
    if constexpr (D::W == 4) {
      const D zero = D::set1(0.0);
      Partials<D> a(zero), b(zero), c(zero);
      {
        const int h0 = r.up_start[i], m = r.up_start[i + 1] - h0;
        int q = 0;
        for (; q + 4 <= m; q += 4) add_upper<D, SP, DP, RO>(r, h0 + q, 4, a, b, c);
        if (q < m) add_upper<D, SP, DP, RO>(r, h0 + q, m - q, a, b, c);
      }
      {
        const int* slot = r.lo_slot + r.lo_start[i];
        const int m = r.lo_start[i + 1] - r.lo_start[i];
        int q = 0;
        for (; q + 4 <= m; q += 4) add_lower<D, SP, DP, RO>(r, slot + q, 4, a, b, c);
        if (q < m) add_lower<D, SP, DP, RO>(r, slot + q, m - q, a, b, c);
      }
      if constexpr (SP) store(se, a.sum());
      if constexpr (DP) store(sd, b.sum());
      if constexpr (RO) store(sr, c.sum());
    } else {
      double p[9][4] = {};
      for (int h = r.up_start[i], q = 0; h < r.up_start[i + 1]; ++h, ++q) {
        const int l = q & 3;
        for (int k = 0; k < 3; ++k) {
          if (SP) p[k][l] += r.F[4 * static_cast<std::ptrdiff_t>(h) + k];
          if (DP) p[3 + k][l] += r.G[4 * static_cast<std::ptrdiff_t>(h) + k];
          if (RO) p[6 + k][l] += r.R[4 * static_cast<std::ptrdiff_t>(h) + k];
        }
      }
      for (int h = r.lo_start[i], q = 0; h < r.lo_start[i + 1]; ++h, ++q) {
        const int l = q & 3;
        const std::ptrdiff_t s = 4 * static_cast<std::ptrdiff_t>(r.lo_slot[h]);
        for (int k = 0; k < 3; ++k) {
          if (SP) p[k][l] += 0.0 - r.F[s + k];
          if (DP) p[3 + k][l] += 0.0 - r.G[s + k];
          if (RO) p[6 + k][l] += r.R[s + k];
        }
      }
      for (int k = 0; k < 3; ++k) {
        se[k] = (p[k][0] + p[k][1]) + (p[k][2] + p[k][3]);
        sd[k] = (p[3 + k][0] + p[3 + k][1]) + (p[3 + k][2] + p[3 + k][3]);
        sr[k] = (p[6 + k][0] + p[6 + k][1]) + (p[6 + k][2] + p[6 + k][3]);
      }
    }
    for (int k = 0; k < 3; ++k) {
      if (SP) r.f[3 * node + k] += se[k];
      if (DP) r.f[3 * node + k] += sd[k];
      if (r.f_spring) r.f_spring[3 * node + k] = se[k];
      if (r.f_dashpot) r.f_dashpot[3 * node + k] = sd[k];
      if (RO) r.rows[3 * node + k] += sr[k];
    }
    if constexpr (EN) {
      // The node's upper springs' energy: partial q % 4 in list order.
      double pe[4] = {0.0, 0.0, 0.0, 0.0};
      for (int h = r.up_start[i], q = 0; h < r.up_start[i + 1]; ++h, ++q) pe[q & 3] += r.e[h];
      r.energy[node] = (pe[0] + pe[1]) + (pe[2] + pe[3]);
    }
  }
}

template <class D>
void spring_sum(const SpringSumRun& r) {
  const int key = (r.F ? 8 : 0) | (r.G ? 4 : 0) | (r.R ? 2 : 0) | (r.e ? 1 : 0);
  switch (key) {
    case 0: return sum_nodes<D, false, false, false, false>(r);
    case 1: return sum_nodes<D, false, false, false, true>(r);
    case 2: return sum_nodes<D, false, false, true, false>(r);
    case 3: return sum_nodes<D, false, false, true, true>(r);
    case 4: return sum_nodes<D, false, true, false, false>(r);
    case 5: return sum_nodes<D, false, true, false, true>(r);
    case 6: return sum_nodes<D, false, true, true, false>(r);
    case 7: return sum_nodes<D, false, true, true, true>(r);
    case 8: return sum_nodes<D, true, false, false, false>(r);
    case 9: return sum_nodes<D, true, false, false, true>(r);
    case 10: return sum_nodes<D, true, false, true, false>(r);
    case 11: return sum_nodes<D, true, false, true, true>(r);
    case 12: return sum_nodes<D, true, true, false, false>(r);
    case 13: return sum_nodes<D, true, true, false, true>(r);
    case 14: return sum_nodes<D, true, true, true, false>(r);
    default: return sum_nodes<D, true, true, true, true>(r);
  }
}

// ---- The force pass's arithmetic floor (harness bench): sum of 1 / sqrt(a[k]), the eval's one
// square root and one division per spring in its lanes (EvalLanes), nothing else per element.
template <class D>
double sqrt_div(const double* a, std::size_t n) {
  constexpr int W = D::W;
  const D one = D::set1(1.0);
  D acc = D::set1(0.0);
  std::size_t k = 0;
  if constexpr (W > 1)
    for (; k + W <= n; k += W) acc = acc + one / sqrt(D::load(a + k));
  double lanes[W];
  store(lanes, acc);
  double s = 0.0;
  for (int j = 0; j < W; ++j) s += lanes[j];
  for (; k < n; ++k) s += 1.0 / __builtin_sqrt(a[k]);
  return s;
}

// ---- The force pass's floor (harness bench): both ends of every spring gathered as eval_lanes
// gathers them, their distance's square root and its reciprocal summed; nothing stored.
template <class D>
double pass_floor(const double* x, const int* self, const int* other, std::size_t n) {
  constexpr int W = D::W;
  const D one = D::set1(1.0);
  D acc = D::set1(0.0);
  std::size_t k = 0;
  if constexpr (W > 1)
    for (; k + W <= n; k += W) {
      typename D::P d;
      D dx, dy, dz;
      D::gather_diff(x, self + k, other + k, d, dx, dy, dz);
      acc = acc + one / sqrt((dx * dx + dy * dy) + dz * dz);
    }
  double lanes[W];
  store(lanes, acc);
  double s = 0.0;
  for (int j = 0; j < W; ++j) s += lanes[j];
  for (; k < n; ++k) {
    const double* a = x + 3 * static_cast<std::ptrdiff_t>(self[k]);
    const double* b = x + 3 * static_cast<std::ptrdiff_t>(other[k]);
    const double dx = b[0] - a[0], dy = b[1] - a[1], dz = b[2] - a[2];
    s += 1.0 / __builtin_sqrt((dx * dx + dy * dy) + dz * dz);
  }
  return s;
}

}  // namespace

extern const Kernels table;
const Kernels table = {
    voxel_cells<VoxelLanes>,
    bounds<BoundsLanes>,
    cell_range<RangeLanes>,
    spring_eval<EvalLanes, SpringLawKind::linear>,
    spring_eval<EvalLanes, SpringLawKind::cubic>,
    spring_eval<EvalLanes, SpringLawKind::exponential>,
    spring_sum<SpringLanes>,
    sqrt_div<EvalLanes>,
    pass_floor<EvalLanes>,
};

}  // namespace harness::simd::HARNESS_SIMD_NS
