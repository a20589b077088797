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

#if defined(HARNESS_X86_AVX)
namespace {
bool cpu_has_avx512() {
  static const bool has = __builtin_cpu_supports("avx512f");
  return has;
}
}  // namespace

// Eight points per iteration with AVX-512 (three loads, two two-source permutes per coordinate);
// otherwise as batch_avx.
__attribute__((target("avx512f"))) void VoxelIndexer::batch_avx512(const Vec3* p, std::size_t n, int* out) const {
  const double* q = p->data();
  const __m512d c0 = _mm512_set1_pd(c_[0]), c1 = _mm512_set1_pd(c_[1]), c2 = _mm512_set1_pd(c_[2]);
  const __m512d inv = _mm512_set1_pd(inv_);
  const __m512d lo0 = _mm512_set1_pd(lo_[0]), lo1 = _mm512_set1_pd(lo_[1]), lo2 = _mm512_set1_pd(lo_[2]);
  const __m512d hi0 = _mm512_set1_pd(hi_[0]), hi1 = _mm512_set1_pd(hi_[1]), hi2 = _mm512_set1_pd(hi_[2]);
  const __m512d dx = _mm512_set1_pd(dx_), dxy = _mm512_set1_pd(dxy_), none = _mm512_set1_pd(-1.0);
  // Coordinate a of point k is q[3k + a]: from (A, B) = q[0..16) first, then from C = q[16..24).
  const __m512i ax1 = _mm512_setr_epi64(0, 3, 6, 9, 12, 15, 0, 0), ax2 = _mm512_setr_epi64(0, 1, 2, 3, 4, 5, 10, 13);
  const __m512i ay1 = _mm512_setr_epi64(1, 4, 7, 10, 13, 0, 0, 0), ay2 = _mm512_setr_epi64(0, 1, 2, 3, 4, 8, 11, 14);
  const __m512i az1 = _mm512_setr_epi64(2, 5, 8, 11, 14, 0, 0, 0), az2 = _mm512_setr_epi64(0, 1, 2, 3, 4, 9, 12, 15);
  std::size_t k = 0;
  for (; k + 8 <= n; k += 8, q += 24) {
    const __m512d A = _mm512_loadu_pd(q), B = _mm512_loadu_pd(q + 8), C = _mm512_loadu_pd(q + 16);
    const __m512d px = _mm512_permutex2var_pd(_mm512_permutex2var_pd(A, ax1, B), ax2, C);
    const __m512d py = _mm512_permutex2var_pd(_mm512_permutex2var_pd(A, ay1, B), ay2, C);
    const __m512d pz = _mm512_permutex2var_pd(_mm512_permutex2var_pd(A, az1, B), az2, C);
    const __m512d t0 = _mm512_mul_pd(_mm512_sub_pd(px, c0), inv);
    const __m512d t1 = _mm512_mul_pd(_mm512_sub_pd(py, c1), inv);
    const __m512d t2 = _mm512_mul_pd(_mm512_sub_pd(pz, c2), inv);
    const __mmask8 in = _mm512_cmp_pd_mask(t0, lo0, _CMP_GE_OQ) & _mm512_cmp_pd_mask(t0, hi0, _CMP_LT_OQ) &
                        _mm512_cmp_pd_mask(t1, lo1, _CMP_GE_OQ) & _mm512_cmp_pd_mask(t1, hi1, _CMP_LT_OQ) &
                        _mm512_cmp_pd_mask(t2, lo2, _CMP_GE_OQ) & _mm512_cmp_pd_mask(t2, hi2, _CMP_LT_OQ);
    // floor; masked forms of the intrinsics here: GCC 12 warns on the plain ones' pass-through
    const int down = _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC;
    const __m512d i0 = _mm512_sub_pd(_mm512_mask_roundscale_pd(t0, 0xFF, t0, down), lo0);
    const __m512d i1 = _mm512_sub_pd(_mm512_mask_roundscale_pd(t1, 0xFF, t1, down), lo1);
    const __m512d i2 = _mm512_sub_pd(_mm512_mask_roundscale_pd(t2, 0xFF, t2, down), lo2);
    const __m512d lin = _mm512_add_pd(_mm512_add_pd(i0, _mm512_mul_pd(dx, i1)), _mm512_mul_pd(dxy, i2));
    const __m256i cell = _mm512_mask_cvttpd_epi32(_mm256_setzero_si256(), 0xFF, _mm512_mask_blend_pd(in, none, lin));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(out + k), cell);
  }
  for (; k < n; ++k) out[k] = (*this)(p[k]);
  _mm256_zeroupper();
}
#endif

#if defined(HARNESS_X86_AVX)
namespace {
bool cpu_has_avx512_int() {
  static const bool has = __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") &&
                          __builtin_cpu_supports("bmi2");
  return has;
}
}  // namespace

// Eight points per iteration on the coordinates as they lie in memory (x0 y0 z0 x1 ...: lane j of
// load v holds coordinate (8v + j) % 3), so no shuffle before the arithmetic: t = (p - c) / v
// per lane, floor and conversion in one instruction (round toward -inf: exact for t in int
// range; anything else, NaN included, becomes INT_MIN), i = floor(t) - lo as int32, and the range
// test 0 <= i < dims as one unsigned comparison. Only then are the 24 lanes regrouped per point
// (weighted by 1, dims.x, dims.x dims.y, three two-source permutes) and summed. Exact, as the
// scalar operator, whenever |lo| and |lo + dims| < 2^30 on every axis (then no out-of-range t
// can wrap into [0, dims)); operator() checks that before choosing it.
// GCC 12's headers implement the 256 <-> 512-bit casts with an undefined operand and warn on it
// (a false positive): silenced for this function only.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
__attribute__((target("avx2,avx512f,avx512vl,bmi2"))) void VoxelIndexer::batch_avx512_packed(const Vec3* p,
                                                                                            std::size_t n,
                                                                                            int* out) const {
  const double* q = p->data();
  alignas(64) double pc[24];
  alignas(32) int pl[24], pd[24], pw[24];
  const int weight[3] = {1, dx_, dxy_};
  for (int j = 0; j < 24; ++j) {
    pc[j] = c_[j % 3];
    pl[j] = ilo_[j % 3];
    pd[j] = static_cast<int>(hi_[j % 3] - lo_[j % 3]);
    pw[j] = weight[j % 3];
  }
  const __m512d c0 = _mm512_load_pd(pc), c1 = _mm512_load_pd(pc + 8), c2 = _mm512_load_pd(pc + 16);
  const __m512d inv = _mm512_set1_pd(inv_);
#define HARNESS_LD(a) _mm256_load_si256(reinterpret_cast<const __m256i*>(a))
  const __m256i l0 = HARNESS_LD(pl), l1 = HARNESS_LD(pl + 8), l2 = HARNESS_LD(pl + 16);
  const __m256i d0 = HARNESS_LD(pd), d1 = HARNESS_LD(pd + 8), d2 = HARNESS_LD(pd + 16);
  const __m256i w0 = HARNESS_LD(pw), w1 = HARNESS_LD(pw + 8), w2 = HARNESS_LD(pw + 16);
#undef HARNESS_LD
  // Point k's three lanes are 3k, 3k + 1, 3k + 2 of (load 0 | load 1 | load 2).
  const __m512i ix = _mm512_setr_epi32(0, 3, 6, 9, 12, 15, 18, 21, 0, 0, 0, 0, 0, 0, 0, 0);
  const __m512i iy = _mm512_setr_epi32(1, 4, 7, 10, 13, 16, 19, 22, 0, 0, 0, 0, 0, 0, 0, 0);
  const __m512i iz = _mm512_setr_epi32(2, 5, 8, 11, 14, 17, 20, 23, 0, 0, 0, 0, 0, 0, 0, 0);
  const __m256i none = _mm256_set1_epi32(-1), zero8 = _mm256_setzero_si256();
  const __m512i zero16 = _mm512_setzero_si512();
  // (masked forms of the conversion and insertion: GCC 12 warns on the plain ones' pass-through)
  constexpr int down = _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC;
  std::size_t k = 0;
  for (; k + 8 <= n; k += 8, q += 24) {
    const __m256i a =
        _mm256_sub_epi32(_mm512_mask_cvt_roundpd_epi32(zero8, 0xFF, _mm512_mul_pd(_mm512_sub_pd(_mm512_loadu_pd(q), c0), inv), down), l0);
    const __m256i b = _mm256_sub_epi32(
        _mm512_mask_cvt_roundpd_epi32(zero8, 0xFF, _mm512_mul_pd(_mm512_sub_pd(_mm512_loadu_pd(q + 8), c1), inv), down), l1);
    const __m256i c = _mm256_sub_epi32(
        _mm512_mask_cvt_roundpd_epi32(zero8, 0xFF, _mm512_mul_pd(_mm512_sub_pd(_mm512_loadu_pd(q + 16), c2), inv), down), l2);
    const unsigned m = static_cast<unsigned>(_mm256_cmplt_epu32_mask(a, d0)) |
                       static_cast<unsigned>(_mm256_cmplt_epu32_mask(b, d1)) << 8 |
                       static_cast<unsigned>(_mm256_cmplt_epu32_mask(c, d2)) << 16;
    const __mmask8 in = static_cast<__mmask8>(_pext_u32(m & (m >> 1) & (m >> 2), 0x249249u));
    const __m512i ab = _mm512_mask_inserti64x4(zero16, 0xFF, _mm512_zextsi256_si512(_mm256_mullo_epi32(a, w0)),
                                               _mm256_mullo_epi32(b, w1), 1);
    const __m512i cc = _mm512_zextsi256_si512(_mm256_mullo_epi32(c, w2));
    const __m256i X = _mm512_castsi512_si256(_mm512_permutex2var_epi32(ab, ix, cc));
    const __m256i Y = _mm512_castsi512_si256(_mm512_permutex2var_epi32(ab, iy, cc));
    const __m256i Z = _mm512_castsi512_si256(_mm512_permutex2var_epi32(ab, iz, cc));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(out + k),
                        _mm256_mask_blend_epi32(in, none, _mm256_add_epi32(_mm256_add_epi32(X, Y), Z)));
  }
  for (; k < n; ++k) out[k] = (*this)(p[k]);
  _mm256_zeroupper();
}
#pragma GCC diagnostic pop
#endif

void VoxelIndexer::operator()(const Vec3* p, std::size_t n, int* out) const {
#if defined(HARNESS_X86_AVX)
  if (packed_ok_ && cpu_has_avx512_int()) return batch_avx512_packed(p, n, out);
  if (cpu_has_avx512()) return batch_avx512(p, n, out);
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

namespace {

// lo = smallest c[k] as unsigned (so -1 only when every c[k] is -1), hi = largest c[k].
void cell_range_scalar(const int* c, std::size_t n, unsigned& lo, int& hi) {
  unsigned l = ~0u;
  int h = -1;
  for (std::size_t k = 0; k < n; ++k) {
    l = std::min(l, static_cast<unsigned>(c[k]));
    h = std::max(h, c[k]);
  }
  lo = l, hi = h;
}

#if defined(HARNESS_X86_AVX)
bool cpu_has_avx2() {
  static const bool has = __builtin_cpu_supports("avx2");
  return has;
}

__attribute__((target("avx2"))) void cell_range_avx2(const int* c, std::size_t n, unsigned& lo, int& hi) {
  __m256i l = _mm256_set1_epi32(-1), h = _mm256_set1_epi32(-1);
  std::size_t k = 0;
  for (; k + 8 <= n; k += 8) {
    const __m256i v = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(c + k));
    l = _mm256_min_epu32(l, v);
    h = _mm256_max_epi32(h, v);
  }
  alignas(32) unsigned L[8];
  alignas(32) int H[8];
  _mm256_store_si256(reinterpret_cast<__m256i*>(L), l);
  _mm256_store_si256(reinterpret_cast<__m256i*>(H), h);
  _mm256_zeroupper();
  cell_range_scalar(c + k, n - k, lo, hi);
  for (int j = 0; j < 8; ++j) lo = std::min(lo, L[j]), hi = std::max(hi, H[j]);
}
#endif

void cell_range(const int* c, std::size_t n, unsigned& lo, int& hi) {
#if defined(HARNESS_X86_AVX)
  if (cpu_has_avx2()) return cell_range_avx2(c, n, lo, hi);
#endif
  cell_range_scalar(c, n, lo, hi);
}

}  // namespace

void points_bounds(const Points& x, int begin, int end, Vec3& lo, Vec3& hi) {
  const double inf = std::numeric_limits<double>::infinity();
  const int n = std::max(0, end - begin);
  const int T = threads_for(static_cast<std::size_t>(n), 16384);
  double part[64][6];  // per thread: lo xyz, hi xyz
  const int parts = std::min(T, 64);
#pragma omp parallel for num_threads(parts) if(parts > 1) schedule(static, 1)
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
                                 chunk_lo_.capacity() + chunk_hi_.capacity()) * sizeof(int));
}

void VoxelData::allocate(long long max_voxels, int max_nodes) {
  listed_ = 0;
  opened_ = 0;
  count_ = 0;
  head_.assign(static_cast<std::size_t>(max_voxels), -1);
  next_.assign(static_cast<std::size_t>(max_nodes), -1);
  node_cell_.assign(static_cast<std::size_t>(max_nodes), -1);
  const std::size_t chunks = (static_cast<std::size_t>(max_nodes) + kChunk - 1) / kChunk;
  chunk_lo_.assign(chunks, ~0u);
  chunk_hi_.assign(chunks, -1);
}

void VoxelData::fill(const GridGeometry& g, const Points& x, int node_begin, int node_end) {
  prepare(g, x, node_begin, node_end);
  link();
}

void VoxelData::clear() {
  // Every slot the last fill can have set holds a voxel of its layout (geom_) that one of its
  // nodes lies in: all slots of that layout when they are few against the nodes (one sequential
  // pass), else the nodes' own voxels (one pass over the nodes, O(nodes) however sparse).
  const std::size_t n = static_cast<std::size_t>(count_);
  if (n == 0) return;
  const long long nv = geom_.num_voxels();
  if (nv <= 8 * static_cast<long long>(n)) {
    const std::size_t V = static_cast<std::size_t>(nv);
    const int T = threads_for(V, 65536);
#pragma omp parallel for num_threads(T) if(T > 1) schedule(static, 1)
    for (int t = 0; t < T; ++t) {
      std::size_t b, e;
      split_range(V, T, t, b, e);
      std::fill(head_.begin() + static_cast<std::ptrdiff_t>(b), head_.begin() + static_cast<std::ptrdiff_t>(e), -1);
    }
  } else {
    const int T = threads_for(n, 32768);
    const int* cell = node_cell_.data();
    // Several threads may clear one voxel, always to the same value: relaxed atomic stores.
#pragma omp parallel for num_threads(T) if(T > 1) schedule(static)
    for (std::size_t k = 0; k < n; ++k) {
      const int c = cell[k];
      if (c < 0) continue;
      __atomic_store_n(head_.data() + c, -1, __ATOMIC_RELAXED);
    }
  }
  count_ = 0;
  listed_ = 0;
  opened_ = 0;
}

void VoxelData::prepare(const GridGeometry& g, const Points& x, int node_begin, int node_end) {
  if (g.num_voxels() > capacity() || node_end - node_begin > static_cast<int>(next_.size()))
    throw std::logic_error("VoxelData::fill: grid exceeds the allocated capacity");
  clear();
  geom_ = g;
  base_ = node_begin;
  count_ = node_end - node_begin;
  const VoxelIndexer idx(g);
  const std::size_t n = static_cast<std::size_t>(count_);
  const int T = g.num_voxels() > 0 ? threads_for(n, 16384) : 1;
  const int K = static_cast<int>((n + kChunk - 1) / kChunk);
  int* cell = node_cell_.data();
  // Chunks handed out dynamically: a thread the system deschedules delays one small chunk.
#pragma omp parallel for num_threads(T) if(T > 1) schedule(dynamic, 4)
  for (int c = 0; c < K; ++c) {
    const std::size_t b = static_cast<std::size_t>(c) * kChunk, e = std::min(n, b + kChunk);
    idx(x.data() + node_begin + b, e - b, cell + b);
    // The chunk's smallest and largest voxel (as unsigned, -1 is the largest: never the
    // smallest unless every node of the chunk is outside), for link_part to skip the chunk.
    cell_range(cell + b, e - b, chunk_lo_[static_cast<std::size_t>(c)], chunk_hi_[static_cast<std::size_t>(c)]);
  }
}

int VoxelData::link_parts() const {
  // Each part reads every node's voxel once: worth it only for many nodes.
  return geom_.num_voxels() > 0 ? std::min(kMaxLinkParts, threads_for(static_cast<std::size_t>(count_), 65536))
                                : 1;
}

void VoxelData::link_part(int part, int parts) {
  // Part p owns the voxels [p V / parts, (p + 1) V / parts) and visits the nodes in decreasing
  // order: pushing onto the front leaves each list in increasing order, whatever `parts` is.
  // Chunks of nodes (prepare) with no voxel of the part are skipped: nodes outside the region,
  // and, when nearby nodes have nearby indices (lattices, layered meshes), the other parts'.
  // (A single backward pass computing the voxels too was twice as slow at 10^6 nodes: backward
  // streams over x defeat the prefetcher; node_cell_ is 4 bytes a node.)
  std::size_t vb, ve;
  split_range(static_cast<std::size_t>(geom_.num_voxels()), parts, part, vb, ve);
  const unsigned lo = static_cast<unsigned>(vb), len = static_cast<unsigned>(ve - vb);
  const int* cell = node_cell_.data();
  int* head = head_.data();
  int* next = next_.data();
  int listed = 0, opened = 0;
  const int K = static_cast<int>((static_cast<std::size_t>(count_) + kChunk - 1) / kChunk);
  for (int c = K - 1; c >= 0; --c) {
    const std::size_t ci = static_cast<std::size_t>(c);
    if (chunk_hi_[ci] < 0 || chunk_lo_[ci] >= ve || static_cast<std::size_t>(chunk_hi_[ci]) < vb) continue;
    const int b = c * static_cast<int>(kChunk);
    for (int k = std::min(count_, b + static_cast<int>(kChunk)) - 1; k >= b; --k) {
      const int v = cell[k];
      if (static_cast<unsigned>(v) - lo >= len) continue;  // -1 (outside the grid) too
      const int h = head[v];
      opened += h < 0;
      next[k] = h;
      head[v] = k;
      ++listed;
    }
  }
  part_listed_[part] = listed;
  part_opened_[part] = opened;
}

void VoxelData::link_done(int parts) {
  listed_ = opened_ = 0;
  for (int p = 0; p < parts; ++p) {
    listed_ += part_listed_[p];
    opened_ += part_opened_[p];
  }
}

void VoxelData::link() {
  const int P = link_parts();
#pragma omp parallel for num_threads(P) if(P > 1) schedule(static, 1)
  for (int p = 0; p < P; ++p) link_part(p, P);
  link_done(P);
}

}  // namespace harness
