// Lane types of the SIMD kernels, for the instruction set this translation unit is compiled for
// (kernels_<isa>.cpp, with its -m flags): included by kernels.inl only. Every name lands in an
// unnamed namespace inside harness::simd::HARNESS_SIMD_NS (see kernels.hpp for why).
//
// A double lane type D has W lanes, a mask type D::M, and:
//   D::load(p), D::set1(a), store(p, a);
//   D::load_xyz(q, px, py, pz): W consecutive points of q (three doubles each) as x, y, z lanes;
//   D::gather_diff(x, ia, ib, d, dx, dy, dz): lane j the difference x[ib[j]] - x[ia[j]] of two
//   points, both as a point form d (D::P: each lane's x y z together, as a four-lane register
//   holds a point) and as x, y, z lanes;
//   store_points(q, d, c): q[4j + a] = c_j d_j,a (a = 0, 1, 2) per lane j, q[4j + 3] a fourth
//   double no sum adds into a result (0, or NaN for c_j infinite or NaN);
//   store_points_abs(q, d, c, m): q[4j + a] = m_j ? c_j |d_j,a| : 0, q[4j + 3] likewise;
//   + - * /, sqrt, abs (clears the sign bit), floor;
//   le, ge, lt, gt (ordered: false for NaN) giving a mask, mask & mask, ~mask, bits(mask) (bit j: lane j);
//   select(m, a, b) (lane j: m ? a : b); min(a, b) = a < b ? a : b and max(a, b) = a > b ? a : b
//   (the vminpd/vmaxpd rule); store_i32(p, a) (lanes holding integers in int range, to int).
// An integer lane type I has W int32 lanes and I::load, I::set1, store, min_u (as unsigned),
// max_s (as signed).
// Every operation is the IEEE (or exact integer) operation lane by lane, so a lane computes what
// the W = 1 type computes.

#include <cstddef>
#include <cstdint>
#if defined(__AVX__)
#include <immintrin.h>
#elif defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace harness::simd::HARNESS_SIMD_NS {
namespace {  // nothing here has a name another translation unit could share

// ---- One lane (plain C++): the scalar level's only type, every level's remainders.

struct M1 {
  bool v;
};
inline M1 operator&(M1 a, M1 b) { return {static_cast<bool>(a.v & b.v)}; }  // no branch
inline unsigned bits(M1 m) { return m.v; }

struct D1 {
  static constexpr int W = 1;
  using M = M1;
  double v;
  static D1 load(const double* p) { return {*p}; }
  static D1 set1(double a) { return {a}; }
  static void load_xyz(const double* q, D1& px, D1& py, D1& pz) { px = {q[0]}, py = {q[1]}, pz = {q[2]}; }
  struct P {
    double v[3];
  };
  static void gather_diff(const double* x, const int* ia, const int* ib, P& d, D1& dx, D1& dy, D1& dz) {
    const double* a = x + 3 * static_cast<std::ptrdiff_t>(ia[0]);
    const double* b = x + 3 * static_cast<std::ptrdiff_t>(ib[0]);
    d.v[0] = b[0] - a[0], d.v[1] = b[1] - a[1], d.v[2] = b[2] - a[2];
    dx = {d.v[0]}, dy = {d.v[1]}, dz = {d.v[2]};
  }
};
inline D1 operator+(D1 a, D1 b) { return {a.v + b.v}; }
inline D1 operator-(D1 a, D1 b) { return {a.v - b.v}; }
inline D1 operator*(D1 a, D1 b) { return {a.v * b.v}; }
inline D1 operator/(D1 a, D1 b) { return {a.v / b.v}; }
inline D1 sqrt(D1 a) { return {__builtin_sqrt(a.v)}; }
inline D1 abs(D1 a) { return {__builtin_fabs(a.v)}; }
inline D1 floor(D1 t) {
#if defined(__SSE4_1__) || !defined(__SSE2__)
  return {__builtin_floor(t.v)};  // an instruction (roundsd, frintm, ...)
#else
  // Baseline x86-64 has no rounding instruction (std::floor is a libm call there): to nearest by
  // adding and subtracting 1.5 2^52 (exact for |t| < 2^51), minus one where that went up; larger
  // magnitudes (and infinities, and NaN) are their own floor. (+0 for -0: only voxel indices,
  // converted to int, are made of it.)
  if (!(t.v > -2251799813685248.0 && t.v < 2251799813685248.0)) return t;
  const __m128d x = _mm_set_sd(t.v), big = _mm_set_sd(6755399441055744.0);
  const __m128d r = _mm_sub_sd(_mm_add_sd(x, big), big);
  return {_mm_cvtsd_f64(_mm_sub_sd(r, _mm_and_pd(_mm_cmpgt_sd(r, x), _mm_set_sd(1.0))))};  // (no branch)
#endif
}
inline M1 le(D1 a, D1 b) { return {a.v <= b.v}; }
inline M1 ge(D1 a, D1 b) { return {a.v >= b.v}; }
inline M1 lt(D1 a, D1 b) { return {a.v < b.v}; }
inline M1 gt(D1 a, D1 b) { return {a.v > b.v}; }
inline M1 operator~(M1 a) { return {!a.v}; }
inline D1 select(M1 m, D1 a, D1 b) { return m.v ? a : b; }
inline D1 min(D1 a, D1 b) { return {a.v < b.v ? a.v : b.v}; }
inline D1 max(D1 a, D1 b) { return {a.v > b.v ? a.v : b.v}; }
inline void store(double* p, D1 a) { *p = a.v; }
inline void store_points(double* q, const D1::P& d, D1 c) {
  q[0] = c.v * d.v[0], q[1] = c.v * d.v[1], q[2] = c.v * d.v[2], q[3] = 0.0;
}
inline void store_points_abs(double* q, const D1::P& d, D1 c, M1 m) {
  for (int a = 0; a < 3; ++a) q[a] = m.v ? c.v * __builtin_fabs(d.v[a]) : 0.0;
  q[3] = 0.0;
}
inline void store_i32(int* p, D1 a) { *p = static_cast<int>(a.v); }

struct I1 {
  static constexpr int W = 1;
  std::int32_t v;
  static I1 load(const int* p) { return {*p}; }
  static I1 set1(int a) { return {a}; }
};
inline I1 min_u(I1 a, I1 b) { return static_cast<std::uint32_t>(a.v) < static_cast<std::uint32_t>(b.v) ? a : b; }
inline I1 max_s(I1 a, I1 b) { return a.v < b.v ? b : a; }
inline void store(int* p, I1 a) { *p = a.v; }

#if defined(__AVX__)
// ---- AVX and AVX2: four doubles; four int32 in SSE4.1 registers (AVX2: eight).

struct M4 {
  __m256d v;  // all ones or all zeros per lane
};
inline M4 operator&(M4 a, M4 b) { return {_mm256_and_pd(a.v, b.v)}; }
inline unsigned bits(M4 m) { return static_cast<unsigned>(_mm256_movemask_pd(m.v)); }

struct D4 {
  static constexpr int W = 4;
  using M = M4;
  __m256d v;
  static D4 load(const double* p) { return {_mm256_loadu_pd(p)}; }
  static D4 set1(double a) { return {_mm256_set1_pd(a)}; }
  static void load_xyz(const double* q, D4& px, D4& py, D4& pz) {
    // Six pairs: r0 = x0 y0 | x2 y2, r1 = z0 x1 | z2 x3, r2 = y1 z1 | y3 z3, then a shuffle each.
    const __m256d r0 = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(q)), _mm_loadu_pd(q + 6), 1);
    const __m256d r1 = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(q + 2)), _mm_loadu_pd(q + 8), 1);
    const __m256d r2 = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(q + 4)), _mm_loadu_pd(q + 10), 1);
    px = {_mm256_shuffle_pd(r0, r1, 0b1010)};
    py = {_mm256_shuffle_pd(r0, r2, 0b0101)};
    pz = {_mm256_shuffle_pd(r1, r2, 0b1010)};
  }
  struct P {
    __m256d p[4];  // lane j's x y z 0
  };
  static void gather_diff(const double* x, const int* ia, const int* ib, P& d, D4& dx, D4& dy, D4& dz) {
    const __m256i m = _mm256_setr_epi64x(-1, -1, -1, 0);
    auto point = [&](const int* idx, int j) {
      return _mm256_maskload_pd(x + 3 * static_cast<std::ptrdiff_t>(idx[j]), m);
    };
    for (int j = 0; j < 4; ++j) d.p[j] = _mm256_sub_pd(point(ib, j), point(ia, j));
    const __m256d L01 = _mm256_unpacklo_pd(d.p[0], d.p[1]), L23 = _mm256_unpacklo_pd(d.p[2], d.p[3]);
    const __m256d H01 = _mm256_unpackhi_pd(d.p[0], d.p[1]), H23 = _mm256_unpackhi_pd(d.p[2], d.p[3]);
    dx = {_mm256_permute2f128_pd(L01, L23, 0x20)};
    dy = {_mm256_permute2f128_pd(H01, H23, 0x20)};
    dz = {_mm256_permute2f128_pd(L01, L23, 0x31)};
  }
};
inline D4 operator+(D4 a, D4 b) { return {_mm256_add_pd(a.v, b.v)}; }
inline D4 operator-(D4 a, D4 b) { return {_mm256_sub_pd(a.v, b.v)}; }
inline D4 operator*(D4 a, D4 b) { return {_mm256_mul_pd(a.v, b.v)}; }
inline D4 operator/(D4 a, D4 b) { return {_mm256_div_pd(a.v, b.v)}; }
inline D4 sqrt(D4 a) { return {_mm256_sqrt_pd(a.v)}; }
inline D4 abs(D4 a) { return {_mm256_andnot_pd(_mm256_set1_pd(-0.0), a.v)}; }
inline D4 floor(D4 a) { return {_mm256_floor_pd(a.v)}; }
inline M4 le(D4 a, D4 b) { return {_mm256_cmp_pd(a.v, b.v, _CMP_LE_OQ)}; }
inline M4 ge(D4 a, D4 b) { return {_mm256_cmp_pd(a.v, b.v, _CMP_GE_OQ)}; }
inline M4 lt(D4 a, D4 b) { return {_mm256_cmp_pd(a.v, b.v, _CMP_LT_OQ)}; }
inline M4 gt(D4 a, D4 b) { return {_mm256_cmp_pd(a.v, b.v, _CMP_GT_OQ)}; }
inline M4 operator~(M4 a) { return {_mm256_xor_pd(a.v, _mm256_castsi256_pd(_mm256_set1_epi64x(-1)))}; }
inline D4 select(M4 m, D4 a, D4 b) { return {_mm256_blendv_pd(b.v, a.v, m.v)}; }
inline D4 min(D4 a, D4 b) { return {_mm256_min_pd(a.v, b.v)}; }
inline D4 max(D4 a, D4 b) { return {_mm256_max_pd(a.v, b.v)}; }
inline void store(double* p, D4 a) { _mm256_storeu_pd(p, a.v); }
// Lane j of c in all four lanes.
template <int j>
inline __m256d lane_of(__m256d c) {
  const __m256d h = _mm256_permute2f128_pd(c, c, j < 2 ? 0x00 : 0x11);
  return _mm256_permute_pd(h, (j & 1) ? 0xF : 0x0);
}
inline void store_points(double* q, const D4::P& d, D4 c) {
  _mm256_storeu_pd(q, _mm256_mul_pd(lane_of<0>(c.v), d.p[0]));
  _mm256_storeu_pd(q + 4, _mm256_mul_pd(lane_of<1>(c.v), d.p[1]));
  _mm256_storeu_pd(q + 8, _mm256_mul_pd(lane_of<2>(c.v), d.p[2]));
  _mm256_storeu_pd(q + 12, _mm256_mul_pd(lane_of<3>(c.v), d.p[3]));
}
inline void store_points_abs(double* q, const D4::P& d, D4 c, M4 m) {
  const __m256d z = _mm256_setzero_pd(), sign = _mm256_set1_pd(-0.0);
  _mm256_storeu_pd(q, _mm256_blendv_pd(z, _mm256_mul_pd(lane_of<0>(c.v), _mm256_andnot_pd(sign, d.p[0])), lane_of<0>(m.v)));
  _mm256_storeu_pd(q + 4, _mm256_blendv_pd(z, _mm256_mul_pd(lane_of<1>(c.v), _mm256_andnot_pd(sign, d.p[1])), lane_of<1>(m.v)));
  _mm256_storeu_pd(q + 8, _mm256_blendv_pd(z, _mm256_mul_pd(lane_of<2>(c.v), _mm256_andnot_pd(sign, d.p[2])), lane_of<2>(m.v)));
  _mm256_storeu_pd(q + 12, _mm256_blendv_pd(z, _mm256_mul_pd(lane_of<3>(c.v), _mm256_andnot_pd(sign, d.p[3])), lane_of<3>(m.v)));
}
inline void store_i32(int* p, D4 a) { _mm_storeu_si128(reinterpret_cast<__m128i*>(p), _mm256_cvttpd_epi32(a.v)); }

struct I4 {
  static constexpr int W = 4;
  __m128i v;
  static I4 load(const int* p) { return {_mm_loadu_si128(reinterpret_cast<const __m128i*>(p))}; }
  static I4 set1(int a) { return {_mm_set1_epi32(a)}; }
};
inline I4 min_u(I4 a, I4 b) { return {_mm_min_epu32(a.v, b.v)}; }
inline I4 max_s(I4 a, I4 b) { return {_mm_max_epi32(a.v, b.v)}; }
inline void store(int* p, I4 a) { _mm_storeu_si128(reinterpret_cast<__m128i*>(p), a.v); }
#endif

#if defined(__AVX2__)
struct I8 {
  static constexpr int W = 8;
  __m256i v;
  static I8 load(const int* p) { return {_mm256_loadu_si256(reinterpret_cast<const __m256i*>(p))}; }
  static I8 set1(int a) { return {_mm256_set1_epi32(a)}; }
};
inline I8 min_u(I8 a, I8 b) { return {_mm256_min_epu32(a.v, b.v)}; }
inline I8 max_s(I8 a, I8 b) { return {_mm256_max_epi32(a.v, b.v)}; }
inline void store(int* p, I8 a) { _mm256_storeu_si256(reinterpret_cast<__m256i*>(p), a.v); }
#endif

#if defined(__AVX512F__)
// ---- AVX-512: eight doubles, sixteen int32.

struct M8 {
  __mmask8 v;
};
inline M8 operator&(M8 a, M8 b) { return {static_cast<__mmask8>(a.v & b.v)}; }
inline unsigned bits(M8 m) { return m.v; }

struct D8 {
  static constexpr int W = 8;
  using M = M8;
  __m512d v;
  static D8 load(const double* p) { return {_mm512_loadu_pd(p)}; }
  static D8 set1(double a) { return {_mm512_set1_pd(a)}; }
  static void load_xyz(const double* q, D8& px, D8& py, D8& pz) {
    // Three loads A B C; coordinate a of point k is lane 3k + a: from (A, B) first, then from C.
    const __m512d A = _mm512_loadu_pd(q), B = _mm512_loadu_pd(q + 8), C = _mm512_loadu_pd(q + 16);
    const __m512i ax1 = _mm512_setr_epi64(0, 3, 6, 9, 12, 15, 0, 0), ax2 = _mm512_setr_epi64(0, 1, 2, 3, 4, 5, 10, 13);
    const __m512i ay1 = _mm512_setr_epi64(1, 4, 7, 10, 13, 0, 0, 0), ay2 = _mm512_setr_epi64(0, 1, 2, 3, 4, 8, 11, 14);
    const __m512i az1 = _mm512_setr_epi64(2, 5, 8, 11, 14, 0, 0, 0), az2 = _mm512_setr_epi64(0, 1, 2, 3, 4, 9, 12, 15);
    px = {_mm512_permutex2var_pd(_mm512_permutex2var_pd(A, ax1, B), ax2, C)};
    py = {_mm512_permutex2var_pd(_mm512_permutex2var_pd(A, ay1, B), ay2, C)};
    pz = {_mm512_permutex2var_pd(_mm512_permutex2var_pd(A, az1, B), az2, C)};
  }
  struct P {
    __m512d z[4];  // z[k]: lane k's x y z 0 | lane k + 4's x y z 0
  };
  static void gather_diff(const double* x, const int* ia, const int* ib, P& d, D8& dx, D8& dy, D8& dz) {
    auto point = [&](const int* idx, int j) {
      return _mm256_maskz_loadu_pd(0x7, x + 3 * static_cast<std::ptrdiff_t>(idx[j]));
    };
    auto pair = [&](const int* idx, int k) {
      return _mm512_insertf64x4(_mm512_castpd256_pd512(point(idx, k)), point(idx, k + 4), 1);
    };
    for (int k = 0; k < 4; ++k) d.z[k] = _mm512_sub_pd(pair(ib, k), pair(ia, k));
    const __m512d L01 = _mm512_unpacklo_pd(d.z[0], d.z[1]), L23 = _mm512_unpacklo_pd(d.z[2], d.z[3]);
    const __m512d H01 = _mm512_unpackhi_pd(d.z[0], d.z[1]), H23 = _mm512_unpackhi_pd(d.z[2], d.z[3]);
    const __m512i lo = _mm512_setr_epi64(0, 1, 8, 9, 4, 5, 12, 13), hi = _mm512_setr_epi64(2, 3, 10, 11, 6, 7, 14, 15);
    dx = {_mm512_permutex2var_pd(L01, lo, L23)};
    dy = {_mm512_permutex2var_pd(H01, lo, H23)};
    dz = {_mm512_permutex2var_pd(L01, hi, L23)};
  }
};
inline D8 operator+(D8 a, D8 b) { return {_mm512_add_pd(a.v, b.v)}; }
inline D8 operator-(D8 a, D8 b) { return {_mm512_sub_pd(a.v, b.v)}; }
inline D8 operator*(D8 a, D8 b) { return {_mm512_mul_pd(a.v, b.v)}; }
inline D8 operator/(D8 a, D8 b) { return {_mm512_div_pd(a.v, b.v)}; }
inline D8 sqrt(D8 a) { return {_mm512_sqrt_pd(a.v)}; }
inline D8 abs(D8 a) { return {_mm512_abs_pd(a.v)}; }
inline D8 floor(D8 a) { return {_mm512_roundscale_pd(a.v, _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC)}; }
inline M8 le(D8 a, D8 b) { return {_mm512_cmp_pd_mask(a.v, b.v, _CMP_LE_OQ)}; }
inline M8 ge(D8 a, D8 b) { return {_mm512_cmp_pd_mask(a.v, b.v, _CMP_GE_OQ)}; }
inline M8 lt(D8 a, D8 b) { return {_mm512_cmp_pd_mask(a.v, b.v, _CMP_LT_OQ)}; }
inline M8 gt(D8 a, D8 b) { return {_mm512_cmp_pd_mask(a.v, b.v, _CMP_GT_OQ)}; }
inline M8 operator~(M8 a) { return {static_cast<__mmask8>(~a.v)}; }
inline D8 select(M8 m, D8 a, D8 b) { return {_mm512_mask_blend_pd(m.v, b.v, a.v)}; }
inline D8 min(D8 a, D8 b) { return {_mm512_min_pd(a.v, b.v)}; }
inline D8 max(D8 a, D8 b) { return {_mm512_max_pd(a.v, b.v)}; }
inline void store(double* p, D8 a) { _mm512_storeu_pd(p, a.v); }
// Lanes k and k + 4 of c, each four times (the layout of D8::P's z[k]).
inline __m512d lanes_of(__m512d c, int k) {
  return _mm512_permutexvar_pd(_mm512_setr_epi64(k, k, k, k, k + 4, k + 4, k + 4, k + 4), c);
}
inline void store_points(double* q, const D8::P& d, D8 c) {
  for (int k = 0; k < 4; ++k) {
    const __m512d r = _mm512_mul_pd(lanes_of(c.v, k), d.z[k]);
    _mm256_storeu_pd(q + 4 * k, _mm512_castpd512_pd256(r));
    _mm256_storeu_pd(q + 4 * (k + 4), _mm512_extractf64x4_pd(r, 1));
  }
}
inline void store_points_abs(double* q, const D8::P& d, D8 c, M8 m) {
  for (int k = 0; k < 4; ++k) {
    const __mmask8 mk = static_cast<__mmask8>(((m.v >> k) & 1u ? 0x0Fu : 0u) | ((m.v >> (k + 4)) & 1u ? 0xF0u : 0u));
    const __m512d r = _mm512_maskz_mul_pd(mk, lanes_of(c.v, k), _mm512_abs_pd(d.z[k]));
    _mm256_storeu_pd(q + 4 * k, _mm512_castpd512_pd256(r));
    _mm256_storeu_pd(q + 4 * (k + 4), _mm512_extractf64x4_pd(r, 1));
  }
}
inline void store_i32(int* p, D8 a) {
  _mm256_storeu_si256(reinterpret_cast<__m256i*>(p), _mm512_cvttpd_epi32(a.v));
}

struct I16 {
  static constexpr int W = 16;
  __m512i v;
  static I16 load(const int* p) { return {_mm512_loadu_si512(p)}; }
  static I16 set1(int a) { return {_mm512_set1_epi32(a)}; }
};
inline I16 min_u(I16 a, I16 b) { return {_mm512_min_epu32(a.v, b.v)}; }
inline I16 max_s(I16 a, I16 b) { return {_mm512_max_epi32(a.v, b.v)}; }
inline void store(int* p, I16 a) { _mm512_storeu_si512(p, a.v); }
#endif

// ---- The lanes each kernel runs with at this level: the widest that pays. The sums of the force
// pass keep four lanes with AVX-512: a register holds one box entry (x y z 0).
#if defined(__AVX512F__)
using VoxelLanes = D8;
using BoundsLanes = D8;
using RangeLanes = I16;
using SpringLanes = D4;
using EvalLanes = D8;
#elif defined(__AVX__)
using VoxelLanes = D4;
using BoundsLanes = D4;
#if defined(__AVX2__)
using RangeLanes = I8;
#else
using RangeLanes = I4;
#endif
using SpringLanes = D4;
using EvalLanes = D4;
#else
using VoxelLanes = D1;
using BoundsLanes = D1;
using RangeLanes = I1;
using SpringLanes = D1;
using EvalLanes = D1;
#endif

}  // namespace
}  // namespace harness::simd::HARNESS_SIMD_NS
