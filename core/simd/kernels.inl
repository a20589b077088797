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

// ---- Spring gather (SpringRun) and dashpots (DashpotRun).
// A node's half-edges are evaluated kChunk at a time, W per iteration, into buffers of forces
// c d, then summed in spring order, skipping those of zero length (the scatter's `if (l <= 0)
// continue`). Every lane does the scalar operations: d = x_j - x_i, l = sqrt((dx^2 + dy^2) +
// dz^2) (Eigen's d.norm()), the law of springs.hpp (the same template the scatter evaluates),
// c * d; for a dashpot ((c u.d) / l2) d with u = v_j - v_i, u.d = (ux dx + uy dy) + uz dz
// (Eigen's dot).
constexpr int kChunk = 64;  // half-edges evaluated at a time: the stack buffers, 64 skip bits
constexpr int kGroup = 4;   // nodes whose sums are interleaved (spring_group)

inline int min_int(int a, int b) { return a < b ? a : b; }

// c d of the m half-edges [a, a + m) of the node at xi (m <= kChunk) into FX, FY, FZ; returns
// the bits of those of zero length. (Always inlined, as each caller's loop wants it.)
template <class D, SpringLawKind K>
[[gnu::always_inline]] inline std::uint64_t spring_chunk(const SpringRun& r, const double* xi, int a, int m,
                                                         double* FX, double* FY, double* FZ) {
  static_assert(K == SpringLawKind::linear || K == SpringLawKind::cubic,
                "the exponential law is evaluated once per spring (spring_forces.cpp)");
  const D x0 = D::set1(xi[0]), x1 = D::set1(xi[1]), x2 = D::set1(xi[2]);
  const D beta = D::set1(r.beta), zero = D::set1(0.0);
  const double* x = r.x;  // (locals: the stores below could alias r's fields)
  const int* oth = r.other + a;
  const double* L0 = r.rest + a;
  const double* K0 = r.stiff + a;
  std::uint64_t skip = 0, unit = 1;  // unit = 2^q (a product, not a variable shift, per iteration)
  int q = 0;
  for (; q + D::W <= m; q += D::W, unit <<= D::W) {
    D px, py, pz;
    D::gather_xyz(x, oth + q, px, py, pz);
    const D dx = px - x0, dy = py - x1, dz = pz - x2;
    const D l = sqrt(dx * dx + dy * dy + dz * dz);
    D c;
    if constexpr (K == SpringLawKind::linear) c = linear_law(D::load(K0 + q), D::load(L0 + q), l);
    else c = cubic_law(D::load(K0 + q), beta, D::load(L0 + q), l);
    store(FX + q, c * dx), store(FY + q, c * dy), store(FZ + q, c * dz);
    skip |= bits(le(l, zero)) * unit;
  }
  if constexpr (D::W > 1)
    if (q < m) skip |= spring_chunk<D1, K>(r, xi, a + q, m - q, FX + q, FY + q, FZ + q) << q;
  return skip;
}

// Node i's sum, any number of half-edges.
template <class D, SpringLawKind K>
void spring_node(const SpringRun& r, int i) {
  alignas(64) double F[3][kChunk];
  const double* xi = r.x + 3 * static_cast<std::ptrdiff_t>(i);
  double* fi = r.f + 3 * static_cast<std::ptrdiff_t>(i);
  double ax = fi[0], ay = fi[1], az = fi[2];
  const int end = r.start[i + 1];
  for (int a = r.start[i]; a < end; a += kChunk) {
    const int m = min_int(kChunk, end - a);
    const std::uint64_t skip = spring_chunk<D, K>(r, xi, a, m, F[0], F[1], F[2]);
    for (int q = 0; q < m; ++q) {
      if ((skip >> q) & 1) continue;
      ax += F[0][q], ay += F[1][q], az += F[2][q];
    }
  }
  fi[0] = ax, fi[1] = ay, fi[2] = az;
}

// Nodes i .. i + kGroup - 1, each with at most kChunk half-edges: their sums, each in spring
// order, interleaved (3 kGroup independent chains of additions instead of three: the latency
// of one addition per half-edge, not the arithmetic, bounds a single node's sum).
template <class D, SpringLawKind K>
void spring_group(const SpringRun& r, int i) {
  alignas(64) double F[kGroup][3][kChunk];
  std::uint64_t skip[kGroup];
  int m[kGroup];
  double acc[kGroup][3];
  int most = 0;
  for (int n = 0; n < kGroup; ++n) {
    const std::ptrdiff_t node = i + n;
    const int a = r.start[node];
    m[n] = r.start[node + 1] - a;
    most = m[n] > most ? m[n] : most;
    skip[n] = spring_chunk<D, K>(r, r.x + 3 * node, a, m[n], F[n][0], F[n][1], F[n][2]);
    for (int c = 0; c < 3; ++c) acc[n][c] = r.f[3 * node + c];
  }
  for (int q = 0; q < most; ++q)
    for (int n = 0; n < kGroup; ++n)
      if (q < m[n] && !((skip[n] >> q) & 1)) acc[n][0] += F[n][0][q], acc[n][1] += F[n][1][q], acc[n][2] += F[n][2][q];
  for (int n = 0; n < kGroup; ++n)
    for (int c = 0; c < 3; ++c) r.f[3 * static_cast<std::ptrdiff_t>(i + n) + c] = acc[n][c];
}

template <class D, SpringLawKind K>
void springs(const SpringRun& r) {
  for (int i = r.i0; i < r.i1;) {
    bool group = i + kGroup <= r.i1;
    for (int n = 0; n < kGroup && group; ++n) group = r.start[i + n + 1] - r.start[i + n] <= kChunk;
    if (group) {
      spring_group<D, K>(r, i);
      i += kGroup;
    } else {
      spring_node<D, K>(r, i);
      ++i;
    }
  }
}

template <class D>
[[gnu::always_inline]] inline std::uint64_t dashpot_chunk(const DashpotRun& r, const double* xi, const double* vi,
                                                          int a, int m, double* FX, double* FY, double* FZ) {
  const D x0 = D::set1(xi[0]), x1 = D::set1(xi[1]), x2 = D::set1(xi[2]);
  const D v0 = D::set1(vi[0]), v1 = D::set1(vi[1]), v2 = D::set1(vi[2]);
  const D cc = D::set1(r.c), zero = D::set1(0.0);
  const double *x = r.x, *v = r.v;  // (locals: the stores below could alias r's fields)
  const int* oth = r.other + a;
  std::uint64_t skip = 0, unit = 1;  // as in spring_chunk
  int q = 0;
  for (; q + D::W <= m; q += D::W, unit <<= D::W) {
    D px, py, pz, ux, uy, uz;
    D::gather_xyz(x, oth + q, px, py, pz);
    D::gather_xyz(v, oth + q, ux, uy, uz);
    const D dx = px - x0, dy = py - x1, dz = pz - x2;
    const D wx = ux - v0, wy = uy - v1, wz = uz - v2;
    const D l2 = dx * dx + dy * dy + dz * dz;
    const D s = cc * (wx * dx + wy * dy + wz * dz) / l2;
    store(FX + q, s * dx), store(FY + q, s * dy), store(FZ + q, s * dz);
    skip |= bits(le(l2, zero)) * unit;
  }
  if constexpr (D::W > 1)
    if (q < m) skip |= dashpot_chunk<D1>(r, xi, vi, a + q, m - q, FX + q, FY + q, FZ + q) << q;
  return skip;
}

template <class D>
void dashpots(const DashpotRun& r) {
  alignas(64) double F[3][kChunk];
  for (int i = r.i0; i < r.i1; ++i) {
    const std::ptrdiff_t node = i;
    double* fi = r.f + 3 * node;
    double ax = fi[0], ay = fi[1], az = fi[2];
    const int end = r.start[i + 1];
    for (int a = r.start[i]; a < end; a += kChunk) {
      const int m = min_int(kChunk, end - a);
      const std::uint64_t skip = dashpot_chunk<D>(r, r.x + 3 * node, r.v + 3 * node, a, m, F[0], F[1], F[2]);
      for (int q = 0; q < m; ++q) {
        if ((skip >> q) & 1) continue;
        ax += F[0][q], ay += F[1][q], az += F[2][q];
      }
    }
    fi[0] = ax, fi[1] = ay, fi[2] = az;
  }
}

}  // namespace

extern const Kernels table;
const Kernels table = {
    voxel_cells<VoxelLanes>,
    bounds<BoundsLanes>,
    cell_range<RangeLanes>,
    springs<SpringLanes, SpringLawKind::linear>,
    springs<SpringLanes, SpringLawKind::cubic>,
    dashpots<SpringLanes>,
};

}  // namespace harness::simd::HARNESS_SIMD_NS
