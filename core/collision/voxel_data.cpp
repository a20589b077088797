#include "core/collision/voxel_data.hpp"

#include "core/parallel.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#endif

namespace harness {

double round_down_pow2(double v) {
  if (!(v > 0.0) || !std::isfinite(v))
    throw std::invalid_argument("voxel size must be finite and > 0, got " + std::to_string(v));
  int e = 0;
  std::frexp(v, &e);  // v = m 2^e with m in [0.5, 1)
  return std::ldexp(1.0, e - 1);
}

int voxel_of(const GridGeometry& g, const Vec3& p, Vec3i* ijk) {
  // 1/v is a power of two: the product equals the quotient (x - c)/v exactly.
  const double inv_v = 1.0 / g.voxel;
  int idx[3];
  for (int a = 0; a < 3; ++a) {
    const double t = std::floor((p[a] - g.center[a]) * inv_v);
    const double lo = g.lo[a];
    // Compared in double: NaN and huge values fail here, so the cast below is always defined.
    if (!(t >= lo && t < lo + g.dims[a])) return -1;
    idx[a] = static_cast<int>(t - lo);
  }
  if (ijk) *ijk = Vec3i(idx[0], idx[1], idx[2]);
  return idx[0] + g.dims.x() * (idx[1] + g.dims.y() * idx[2]);
}

Vec3i voxel_ijk(const GridGeometry& g, int cell) {
  const int ix = cell % g.dims.x();
  const int r = cell / g.dims.x();
  return Vec3i(ix, r % g.dims.y(), r / g.dims.y());
}

#if defined(__x86_64__) && defined(__GNUC__)
#define HARNESS_X86_AVX 1
namespace {
bool cpu_has_avx() {
  static const bool has = __builtin_cpu_supports("avx");
  return has;
}
}  // namespace

// Four points per iteration: the twelve coordinates are loaded as six pairs and shuffled into
// x, y, z vectors; t = (p - c) / v, the range test and floor are the scalar operator's, the
// linear index is formed in double (exact: integers below 2^31) and out-of-range lanes get -1.
__attribute__((target("avx"))) void VoxelIndexer::batch_avx(const Vec3* p, std::size_t n, int* out) const {
  const double* q = p->data();
  const __m256d c0 = _mm256_set1_pd(c_[0]), c1 = _mm256_set1_pd(c_[1]), c2 = _mm256_set1_pd(c_[2]);
  const __m256d inv = _mm256_set1_pd(inv_);
  const __m256d lo0 = _mm256_set1_pd(lo_[0]), lo1 = _mm256_set1_pd(lo_[1]), lo2 = _mm256_set1_pd(lo_[2]);
  const __m256d hi0 = _mm256_set1_pd(hi_[0]), hi1 = _mm256_set1_pd(hi_[1]), hi2 = _mm256_set1_pd(hi_[2]);
  const __m256d dx = _mm256_set1_pd(dx_), dxy = _mm256_set1_pd(dxy_), none = _mm256_set1_pd(-1.0);
  std::size_t k = 0;
  for (; k + 4 <= n; k += 4, q += 12) {
    // r0 = x0 y0 | x2 y2, r1 = z0 x1 | z2 x3, r2 = y1 z1 | y3 z3
    const __m256d r0 = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(q)), _mm_loadu_pd(q + 6), 1);
    const __m256d r1 = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(q + 2)), _mm_loadu_pd(q + 8), 1);
    const __m256d r2 = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(q + 4)), _mm_loadu_pd(q + 10), 1);
    const __m256d t0 = _mm256_mul_pd(_mm256_sub_pd(_mm256_shuffle_pd(r0, r1, 0b1010), c0), inv);
    const __m256d t1 = _mm256_mul_pd(_mm256_sub_pd(_mm256_shuffle_pd(r0, r2, 0b0101), c1), inv);
    const __m256d t2 = _mm256_mul_pd(_mm256_sub_pd(_mm256_shuffle_pd(r1, r2, 0b1010), c2), inv);
    const __m256d in = _mm256_and_pd(
        _mm256_and_pd(_mm256_and_pd(_mm256_cmp_pd(t0, lo0, _CMP_GE_OQ), _mm256_cmp_pd(t0, hi0, _CMP_LT_OQ)),
                      _mm256_and_pd(_mm256_cmp_pd(t1, lo1, _CMP_GE_OQ), _mm256_cmp_pd(t1, hi1, _CMP_LT_OQ))),
        _mm256_and_pd(_mm256_cmp_pd(t2, lo2, _CMP_GE_OQ), _mm256_cmp_pd(t2, hi2, _CMP_LT_OQ)));
    const __m256d i0 = _mm256_sub_pd(_mm256_floor_pd(t0), lo0);
    const __m256d i1 = _mm256_sub_pd(_mm256_floor_pd(t1), lo1);
    const __m256d i2 = _mm256_sub_pd(_mm256_floor_pd(t2), lo2);
    const __m256d lin = _mm256_add_pd(_mm256_add_pd(i0, _mm256_mul_pd(dx, i1)), _mm256_mul_pd(dxy, i2));
    _mm_storeu_si128(reinterpret_cast<__m128i*>(out + k), _mm256_cvttpd_epi32(_mm256_blendv_pd(none, lin, in)));
  }
  for (; k < n; ++k) out[k] = (*this)(p[k]);
  _mm256_zeroupper();
}
#endif

void VoxelIndexer::operator()(const Vec3* p, std::size_t n, int* out) const {
#if defined(HARNESS_X86_AVX)
  if (cpu_has_avx()) return batch_avx(p, n, out);
#endif
  for (std::size_t k = 0; k < n; ++k) out[k] = (*this)(p[k]);
}

namespace {

// lo/hi of the coordinates of points [b, e) (6 doubles: lo xyz, hi xyz), as (p < l) ? p : l and
// (h < p) ? p : h per coordinate.
void bounds_scalar(const Vec3* x, std::size_t b, std::size_t e, double* r) {
  const double inf = std::numeric_limits<double>::infinity();
  double l0 = inf, l1 = inf, l2 = inf, h0 = -inf, h1 = -inf, h2 = -inf;
  for (std::size_t k = b; k < e; ++k) {
    const Vec3& p = x[k];
    l0 = p[0] < l0 ? p[0] : l0;
    l1 = p[1] < l1 ? p[1] : l1;
    l2 = p[2] < l2 ? p[2] : l2;
    h0 = h0 < p[0] ? p[0] : h0;
    h1 = h1 < p[1] ? p[1] : h1;
    h2 = h2 < p[2] ? p[2] : h2;
  }
  r[0] = l0, r[1] = l1, r[2] = l2, r[3] = h0, r[4] = h1, r[5] = h2;
}

#if defined(HARNESS_X86_AVX)
// Four points (twelve doubles, three loads) per iteration with one accumulator per load
// position; the lanes are folded per coordinate at the end. vminpd(p, l) is (p < l) ? p : l
// and vmaxpd(p, h) is (p > h) ? p : h: the scalar rule, NaN included.
__attribute__((target("avx"))) void bounds_avx(const Vec3* x, std::size_t b, std::size_t e, double* r) {
  const double inf = std::numeric_limits<double>::infinity();
  __m256d la = _mm256_set1_pd(inf), lb = la, lc = la;
  __m256d ha = _mm256_set1_pd(-inf), hb = ha, hc = ha;
  std::size_t k = b;
  for (; k + 4 <= e; k += 4) {
    const double* q = x[k].data();
    const __m256d a = _mm256_loadu_pd(q), bb = _mm256_loadu_pd(q + 4), c = _mm256_loadu_pd(q + 8);
    la = _mm256_min_pd(a, la), lb = _mm256_min_pd(bb, lb), lc = _mm256_min_pd(c, lc);
    ha = _mm256_max_pd(a, ha), hb = _mm256_max_pd(bb, hb), hc = _mm256_max_pd(c, hc);
  }
  alignas(32) double L[12], H[12];
  _mm256_store_pd(L, la), _mm256_store_pd(L + 4, lb), _mm256_store_pd(L + 8, lc);
  _mm256_store_pd(H, ha), _mm256_store_pd(H + 4, hb), _mm256_store_pd(H + 8, hc);
  _mm256_zeroupper();  // before legacy-SSE code: dirty upper halves cost a false dependency each
  bounds_scalar(x, k, e, r);
  // Lane j of the 12 holds coordinate j % 3 of some point.
  for (int j = 0; j < 12; ++j) {
    const int a = j % 3;
    r[a] = L[j] < r[a] ? L[j] : r[a];
    r[3 + a] = r[3 + a] < H[j] ? H[j] : r[3 + a];
  }
}
#endif

}  // namespace

void points_bounds(const Points& x, int begin, int end, Vec3& lo, Vec3& hi) {
  const double inf = std::numeric_limits<double>::infinity();
  const int n = std::max(0, end - begin);
  const int T = threads_for(static_cast<std::size_t>(n), 16384);
  double part[64][6];  // per thread: lo xyz, hi xyz
  const int parts = std::min(T, 64);
#pragma omp parallel for num_threads(parts) schedule(static, 1)
  for (int t = 0; t < parts; ++t) {
    std::size_t b, e;
    split_range(static_cast<std::size_t>(n), parts, t, b, e);
    const Vec3* p = x.data() + begin;
#if defined(HARNESS_X86_AVX)
    if (cpu_has_avx()) {
      bounds_avx(p, b, e, part[t]);
      continue;
    }
#endif
    bounds_scalar(p, b, e, part[t]);
  }
  lo = Vec3::Constant(inf);
  hi = Vec3::Constant(-inf);
  for (int t = 0; t < parts; ++t)
    for (int a = 0; a < 3; ++a) {
      lo[a] = part[t][a] < lo[a] ? part[t][a] : lo[a];
      hi[a] = hi[a] < part[t][3 + a] ? part[t][3 + a] : hi[a];
    }
  // min and max are exact; only the sign of a zero could depend on the order of the points.
  lo = lo + Vec3::Zero();
  hi = hi + Vec3::Zero();
}

long long VoxelData::bytes() const {
  return static_cast<long long>((head_.capacity() + next_.capacity() + node_cell_.capacity() +
                                 occupied_.capacity() + occ_scratch_.capacity() + bucket_.capacity()) *
                                    sizeof(int) +
                                table_.capacity() * sizeof(long long));
}

void VoxelData::allocate(long long max_voxels, int max_nodes) {
  occupied_.clear();
  listed_ = 0;
  head_.assign(static_cast<std::size_t>(max_voxels), -1);
  next_.assign(static_cast<std::size_t>(max_nodes), -1);
  node_cell_.assign(static_cast<std::size_t>(max_nodes), -1);
  // Every listed node can open at most one voxel.
  occupied_.reserve(static_cast<std::size_t>(max_nodes));
  occ_scratch_.assign(static_cast<std::size_t>(max_nodes), 0);
  if (!bucket_.empty() || threads() > 1) bucket_.assign(static_cast<std::size_t>(max_nodes), 0);
}

void VoxelData::fill(const GridGeometry& g, const Points& x, int node_begin, int node_end) {
  if (g.num_voxels() > capacity() || node_end - node_begin > static_cast<int>(next_.size()))
    throw std::logic_error("VoxelData::fill: grid exceeds the allocated capacity");
  // Clear by the previous occupancy list: slots are linear indices, valid whatever the layout.
  {
    const std::size_t no = occupied_.size();
    const int T = threads_for(no, 32768);
#pragma omp parallel for num_threads(T) schedule(static)
    for (std::size_t i = 0; i < no; ++i) head_[occupied_[i]] = -1;
  }
  occupied_.clear();
  geom_ = g;
  base_ = node_begin;
  const VoxelIndexer idx(g);
  const int n = node_end - node_begin;
  const int T = g.num_voxels() > 0 ? std::min(64, threads_for(static_cast<std::size_t>(n), 16384)) : 1;
  if (T == 1)
    fill_serial(idx, x, node_begin, node_end);
  else
    fill_parallel(T, idx, x, node_begin, node_end);
}

void VoxelData::fill_serial(const VoxelIndexer& idx, const Points& x, int node_begin, int node_end) {
  const int n = node_end - node_begin;
  idx(x.data() + node_begin, static_cast<std::size_t>(n), node_cell_.data());
  int* occ = occ_scratch_.data();
  int no = 0, listed = 0;
  // Decreasing node order: pushing onto the front leaves each list in increasing order.
  for (int k = n - 1; k >= 0; --k) {
    const int c = node_cell_[k];
    if (c < 0) continue;
    const int h = head_[c];
    occ[no] = c;  // kept only when the voxel was empty (branch-free)
    no += h < 0;
    next_[k] = h;
    head_[c] = k;
    ++listed;
  }
  listed_ = listed;
  occupied_.assign(occ, occ + no);  // within reserved capacity
}

void VoxelData::fill_parallel(int T, const VoxelIndexer& idx, const Points& x, int node_begin,
                              int node_end) {
  const std::size_t n = static_cast<std::size_t>(node_end - node_begin);
  if (bucket_.size() < next_.size()) bucket_.assign(next_.size(), 0);  // first parallel fill only
  // Tables: cnt[t][s] (T x T), then slab starts (T + 1), then occupied per slab (T).
  const std::size_t TT = static_cast<std::size_t>(T) * static_cast<std::size_t>(T);
  if (table_.size() < TT + 2 * static_cast<std::size_t>(T) + 1) table_.assign(TT + 2 * T + 1, 0);
  long long* cnt = table_.data();
  long long* slab_start = cnt + TT;
  long long* slab_occ = slab_start + T + 1;
  const long long nv = geom_.num_voxels();
  long long vb[65];
  for (int s = 0; s <= T; ++s) vb[s] = nv * s / T;
  auto slab_of = [&](int c) {
    int s = 0;
    while (s + 1 < T && c >= vb[s + 1]) ++s;
    return s;
  };

  // 1. Voxel of every node, counted per (chunk, slab).
#pragma omp parallel for num_threads(T) schedule(static, 1)
  for (int t = 0; t < T; ++t) {
    std::size_t b, e;
    split_range(n, T, t, b, e);
    long long* my = cnt + static_cast<std::size_t>(t) * T;
    for (int s = 0; s < T; ++s) my[s] = 0;
    idx(x.data() + node_begin + b, e - b, node_cell_.data() + b);
    for (std::size_t k = b; k < e; ++k) {
      const int c = node_cell_[k];
      if (c >= 0) ++my[slab_of(c)];
    }
  }
  // Bucket offsets, slab-major, chunk order within a slab: cnt becomes the write cursor.
  long long total = 0;
  for (int s = 0; s < T; ++s) {
    slab_start[s] = total;
    for (int t = 0; t < T; ++t) {
      const long long c = cnt[static_cast<std::size_t>(t) * T + s];
      cnt[static_cast<std::size_t>(t) * T + s] = total;
      total += c;
    }
  }
  slab_start[T] = total;
  listed_ = static_cast<int>(total);

  // 2. Bucket the nodes by slab (each chunk writes its own ranges, in node order).
#pragma omp parallel for num_threads(T) schedule(static, 1)
  for (int t = 0; t < T; ++t) {
    std::size_t b, e;
    split_range(n, T, t, b, e);
    long long* cur = cnt + static_cast<std::size_t>(t) * T;
    for (std::size_t k = b; k < e; ++k) {
      const int c = node_cell_[k];
      if (c >= 0) bucket_[static_cast<std::size_t>(cur[slab_of(c)]++)] = static_cast<int>(k);
    }
  }

  // 3. Each slab builds its lists from its bucket, in decreasing node order; its occupied voxels
  // go to occ_scratch_[slab_start[s], ...) (a slab has at most as many as it has nodes).
#pragma omp parallel for num_threads(T) schedule(static, 1)
  for (int s = 0; s < T; ++s) {
    const long long b = slab_start[s], e = slab_start[s + 1];
    int* occ = occ_scratch_.data() + b;
    int no = 0;
    for (long long q = e - 1; q >= b; --q) {
      const int k = bucket_[static_cast<std::size_t>(q)];
      const int c = node_cell_[k];
      const int h = head_[c];
      occ[no] = c;
      no += h < 0;
      next_[k] = h;
      head_[c] = k;
    }
    slab_occ[s] = no;
  }
  // The occupied list, slab by slab (capacity reserved, no allocation).
  long long no_total = 0;
  for (int s = 0; s < T; ++s) no_total += slab_occ[s];
  occupied_.resize(static_cast<std::size_t>(no_total));
  long long at = 0;
  for (int s = 0; s < T; ++s) {
    std::copy_n(occ_scratch_.data() + slab_start[s], slab_occ[s], occupied_.data() + at);
    at += slab_occ[s];
  }
}

}  // namespace harness
