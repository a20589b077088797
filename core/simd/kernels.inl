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
// The sums use four lanes (D4) at every SIMD level, one (D1) at the scalar level; lane l of a
// four-lane iteration starting at half-edge q (a multiple of four) is partial sum (q + l) % 4 = l,
// and the scalar level puts half-edge q into partial q % 4: the same partial sums, and the same
// (p0 + p1) + (p2 + p3), at every level.
constexpr double kLaneIndex[4] = {0.0, 1.0, 2.0, 3.0};

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

// The law at the lanes' lengths (springs.hpp, each expression as the scalar one): c the tension
// over length, t the tangent stiffness over l2 (want_t), e the energy (want_e), from s = l - L0,
// r = 1 / l and q = 1 / L0. What is not wanted is not computed.
template <class D, SpringLawKind K>
[[gnu::always_inline]] inline void law_lanes(const LawConstants<D>& C, const D& k, const D& L0, const D& q,
                                             const D& l, const D& r, bool want_t, bool want_e, D& c, D& t,
                                             D& e) {
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
    D em1 = expm1_halving(x, C.coef, C.eighth, C.two);
    const unsigned in = bits(le(abs(x), C.direct));
    if (in != (1u << D::W) - 1u) {  // beyond the polynomial's range (or NaN): libm, lane by lane
      double xs[D::W], es[D::W];
      store(xs, x), store(es, em1);
      for (int j = 0; j < D::W; ++j)
        if (!((in >> j) & 1u)) es[j] = __builtin_expm1(xs[j]);
      em1 = D::load(es);
    }
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
template <class D, SpringLawKind K>
[[gnu::always_inline]] inline void eval_lanes(const SpringEvalRun& r, const LawConstants<D>& C, int h) {
  D ax, ay, az, bx, by, bz;
  D::gather_xyz(r.x, r.self + h, ax, ay, az);
  D::gather_xyz(r.x, r.other + h, bx, by, bz);
  const D dx = bx - ax, dy = by - ay, dz = bz - az;
  const D l2 = (dx * dx + dy * dy) + dz * dz;
  const auto zero_length = le(l2, C.zero);  // l <= 0 exactly when l2 <= 0 (NaN: neither)
  const bool springs = r.F[0] != nullptr, rows = r.R[0] != nullptr, energy = r.e != nullptr;
  const D l = sqrt(l2);
  const D rl = C.one / l;  // the pass's one division: 1 / l
  if (springs || rows || energy) {
    D c = C.zero, t = C.zero, e = C.zero;
    law_lanes<D, K>(C, D::load(r.stiff + h), D::load(r.rest + h), D::load(r.inv_rest + h), l, rl, rows, energy, c, t,
                    e);
    if (springs) {
      store(r.F[0] + h, select(zero_length, C.zero, c * dx));
      store(r.F[1] + h, select(zero_length, C.zero, c * dy));
      store(r.F[2] + h, select(zero_length, C.zero, c * dz));
    }
    if (rows) {
      const auto ok = lt(C.zero, l2);
      const D adx = abs(dx), ady = abs(dy), adz = abs(dz);
      const D rr = C.two * t * ((adx + ady) + adz);
      store(r.R[0] + h, select(ok, rr * adx, C.zero));
      store(r.R[1] + h, select(ok, rr * ady, C.zero));
      store(r.R[2] + h, select(ok, rr * adz, C.zero));
    }
    if (energy) store(r.e + h, e);
  }
  if (r.G[0]) {
    D ux, uy, uz, wx, wy, wz;
    D::gather_xyz(r.v, r.self + h, ux, uy, uz);
    D::gather_xyz(r.v, r.other + h, wx, wy, wz);
    ux = wx - ux, uy = wy - uy, uz = wz - uz;
    const D s = C.damping * ((ux * dx + uy * dy) + uz * dz) * (rl * rl);
    store(r.G[0] + h, select(zero_length, C.zero, s * dx));
    store(r.G[1] + h, select(zero_length, C.zero, s * dy));
    store(r.G[2] + h, select(zero_length, C.zero, s * dz));
  }
}

template <class D, SpringLawKind K>
void spring_eval(const SpringEvalRun& r) {
  int h = r.h0;
  if constexpr (D::W > 1) {
    const LawConstants<D> C(r.beta, r.damping);
    for (; h + D::W <= r.h1; h += D::W) eval_lanes<D, K>(r, C, h);
  }
  const LawConstants<D1> C1(r.beta, r.damping);
  for (; h < r.h1; ++h) eval_lanes<D1, K>(r, C1, h);
}

// ---- The summing half (SpringSumRun): four half-edges per iteration, lane l into partial l, the
// partial sums in registers over a node's upper then lower list; the last iteration of a list
// masks the lanes past its end (the next node's entries or the padding: read, never added). The
// scalar level goes one half-edge at a time into partial q % 4. What a pass does not want
// (springs, dashpots, rows, energy) is compiled out (one variant per combination). Adding +0 to a
// partial sum, which is never -0, leaves it as it is: a masked lane adds nothing.

// The node's sums from its partials p[quantity][partial]: springs x y z, dashpots x y z, rows
// x y z, energy.
template <bool SP, bool DP, bool RO, bool EN>
[[gnu::always_inline]] inline void finish(const SpringSumRun& r, std::ptrdiff_t node, const double (*p)[4]) {
  for (int a = 0; a < 3; ++a) {
    const double se = (p[a][0] + p[a][1]) + (p[a][2] + p[a][3]);
    const double sd = (p[3 + a][0] + p[3 + a][1]) + (p[3 + a][2] + p[3 + a][3]);
    if (SP) r.f[3 * node + a] += se;
    if (DP) r.f[3 * node + a] += sd;
    if (r.f_spring) r.f_spring[3 * node + a] = se;
    if (r.f_dashpot) r.f_dashpot[3 * node + a] = sd;
    if (RO) r.rows[3 * node + a] += (p[6 + a][0] + p[6 + a][1]) + (p[6 + a][2] + p[6 + a][3]);
  }
  if (EN) r.energy[node] = (p[9][0] + p[9][1]) + (p[9][2] + p[9][3]);
}

template <class D, bool SP, bool DP, bool RO, bool EN>
void sum_nodes(const SpringSumRun& r) {
  for (int i = r.i0; i < r.i1; ++i) {
    const std::ptrdiff_t node = i;
    alignas(32) double p[10][4] = {};
    if constexpr (D::W == 4) {
      const D zero = D::set1(0.0), lane = D::load(kLaneIndex);
      D a0 = zero, a1 = zero, a2 = zero, b0 = zero, b1 = zero, b2 = zero, c0 = zero, c1 = zero, c2 = zero, es = zero;
      // Upper half-edges: contiguous box entries, +F, +G, +R, +e.
      {
        const int a = r.up_start[i], m = r.up_start[i + 1] - a;
        for (int q = 0; q < m; q += 4) {
          const int h = a + q;
          const auto in = lt(lane, D::set1(static_cast<double>(m - q)));
          if constexpr (SP) {
            a0 = a0 + select(in, D::load(r.F[0] + h), zero), a1 = a1 + select(in, D::load(r.F[1] + h), zero);
            a2 = a2 + select(in, D::load(r.F[2] + h), zero);
          }
          if constexpr (DP) {
            b0 = b0 + select(in, D::load(r.G[0] + h), zero), b1 = b1 + select(in, D::load(r.G[1] + h), zero);
            b2 = b2 + select(in, D::load(r.G[2] + h), zero);
          }
          if constexpr (RO) {
            c0 = c0 + select(in, D::load(r.R[0] + h), zero), c1 = c1 + select(in, D::load(r.R[1] + h), zero);
            c2 = c2 + select(in, D::load(r.R[2] + h), zero);
          }
          if constexpr (EN) es = es + select(in, D::load(r.e + h), zero);
        }
      }
      // Lower half-edges: the same spring's upper entry through lo_slot, -F, -G, +R.
      {
        const int a = r.lo_start[i], m = r.lo_start[i + 1] - a;
        for (int q = 0; q < m; q += 4) {
          const int* slot = r.lo_slot + a + q;
          const auto in = lt(lane, D::set1(static_cast<double>(m - q)));
          if constexpr (SP) {
            a0 = a0 + select(in, zero - D::gather(r.F[0], slot), zero);
            a1 = a1 + select(in, zero - D::gather(r.F[1], slot), zero);
            a2 = a2 + select(in, zero - D::gather(r.F[2], slot), zero);
          }
          if constexpr (DP) {
            b0 = b0 + select(in, zero - D::gather(r.G[0], slot), zero);
            b1 = b1 + select(in, zero - D::gather(r.G[1], slot), zero);
            b2 = b2 + select(in, zero - D::gather(r.G[2], slot), zero);
          }
          if constexpr (RO) {
            c0 = c0 + select(in, D::gather(r.R[0], slot), zero), c1 = c1 + select(in, D::gather(r.R[1], slot), zero);
            c2 = c2 + select(in, D::gather(r.R[2], slot), zero);
          }
        }
      }
      store(p[0], a0), store(p[1], a1), store(p[2], a2), store(p[3], b0), store(p[4], b1), store(p[5], b2);
      store(p[6], c0), store(p[7], c1), store(p[8], c2), store(p[9], es);
    } else {
      for (int h = r.up_start[i], q = 0; h < r.up_start[i + 1]; ++h, ++q) {
        const int l = q & 3;
        for (int c = 0; c < 3; ++c) {
          if (SP) p[c][l] += r.F[c][h];
          if (DP) p[3 + c][l] += r.G[c][h];
          if (RO) p[6 + c][l] += r.R[c][h];
        }
        if (EN) p[9][l] += r.e[h];
      }
      for (int h = r.lo_start[i], q = 0; h < r.lo_start[i + 1]; ++h, ++q) {
        const int l = q & 3, k = r.lo_slot[h];
        for (int c = 0; c < 3; ++c) {
          if (SP) p[c][l] += 0.0 - r.F[c][k];
          if (DP) p[3 + c][l] += 0.0 - r.G[c][k];
          if (RO) p[6 + c][l] += r.R[c][k];
        }
      }
    }
    finish<SP, DP, RO, EN>(r, node, p);
  }
}

template <class D>
void spring_sum(const SpringSumRun& r) {
  const int key = (r.F[0] ? 8 : 0) | (r.G[0] ? 4 : 0) | (r.R[0] ? 2 : 0) | (r.e ? 1 : 0);
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
};

}  // namespace harness::simd::HARNESS_SIMD_NS
