#include "core/springs.hpp"

#include "core/cpu.hpp"

#include <cmath>

#if defined(HARNESS_HAVE_MVEC)
#include <immintrin.h>
extern "C" __attribute__((target("avx2"))) __m256d _ZGVdN4v_expm1(__m256d);  // glibc libmvec
extern "C" __attribute__((target("avx2"))) __m256d _ZGVdN4v_exp(__m256d);
#endif

namespace harness {

namespace {
// (exp(x) - 1 - x) / x^2, accurate near 0 where the direct formula cancels.
double exp_energy_kernel(double x) {
  if (std::fabs(x) < 1e-3) return 0.5 + x / 6.0 + x * x / 24.0 + x * x * x / 120.0;
  return (std::expm1(x) - x) / (x * x);
}
// expm1(x)/x, accurate near 0.
double expm1_over_x(double x) {
  if (std::fabs(x) < 1e-8) return 1.0 + 0.5 * x;
  return std::expm1(x) / x;
}
}  // namespace

#if defined(HARNESS_HAVE_MVEC)
namespace {
// Whenever the processor has AVX2, whatever level the kernels run at (HARNESS_ISA=scalar
// included): expm1 is a choice of math library, not a kernel path, and the golden state hashes
// were recorded with libmvec (core/cpu.hpp).
bool use_mvec() {
  static const bool has = isa_supported(Isa::avx2);
  return has;
}
__attribute__((target("avx2"))) void expm1_4(const double* x, double* out) {
  _mm256_storeu_pd(out, _ZGVdN4v_expm1(_mm256_loadu_pd(x)));
}
__attribute__((target("avx2"))) void exp_4(const double* x, double* out) {
  _mm256_storeu_pd(out, _ZGVdN4v_exp(_mm256_loadu_pd(x)));
}
// f over x[0, n) four at a time (the last block padded with zeros).
template <class F>
void by_fours(F f, const double* x, double* out, int n) {
  int i = 0;
  for (; i + 4 <= n; i += 4) f(x + i, out + i);
  if (i < n) {
    double in[4] = {0.0, 0.0, 0.0, 0.0}, o[4];
    for (int j = i; j < n; ++j) in[j - i] = x[j];
    f(in, o);
    for (int j = i; j < n; ++j) out[j] = o[j - i];
  }
}
}  // namespace
#endif

double spring_expm1(double x) {
#if defined(HARNESS_HAVE_MVEC)
  if (use_mvec()) {
    const double in[4] = {x, x, x, x};
    double out[4];
    expm1_4(in, out);
    return out[0];
  }
#endif
  return std::expm1(x);
}

void spring_expm1_batch(const double* x, double* out, int n) {
#if defined(HARNESS_HAVE_MVEC)
  if (use_mvec()) return by_fours(expm1_4, x, out, n);
#endif
  for (int i = 0; i < n; ++i) out[i] = std::expm1(x[i]);
}

void spring_exp_batch(const double* x, double* out, int n) {
#if defined(HARNESS_HAVE_MVEC)
  if (use_mvec()) return by_fours(exp_4, x, out, n);
#endif
  for (int i = 0; i < n; ++i) out[i] = std::exp(x[i]);
}

double spring_tension(const SpringLaw& law, double L0, double l) {
  const double eps = (l - L0) / L0;
  switch (law.kind) {
    case SpringLawKind::linear: return law.k * L0 * eps;
    case SpringLawKind::cubic: return law.k * L0 * (eps + law.beta * eps * eps * eps);
    case SpringLawKind::exponential: return law.k * L0 * eps * expm1_over_x(law.beta * eps);
  }
  return 0.0;
}

double spring_force_per_length(const SpringLaw& law, double L0, double l) {
  switch (law.kind) {
    case SpringLawKind::linear: return linear_per_length(law, L0, l);
    case SpringLawKind::cubic: return cubic_per_length(law, L0, l);
    case SpringLawKind::exponential: {
      const double x = exponential_arg(law, L0, l);
      return exponential_per_length(law, L0, l, x, spring_expm1(x));
    }
  }
  return 0.0;
}

double spring_energy(const SpringLaw& law, double L0, double l) {
  const double eps = (l - L0) / L0;
  const double kL2 = law.k * L0 * L0;
  switch (law.kind) {
    case SpringLawKind::linear: return 0.5 * kL2 * eps * eps;
    case SpringLawKind::cubic:
      return kL2 * (0.5 * eps * eps + 0.25 * law.beta * eps * eps * eps * eps);
    case SpringLawKind::exponential:
      return kL2 * eps * eps * exp_energy_kernel(law.beta * eps);
  }
  return 0.0;
}

double spring_tangent(const SpringLaw& law, double L0, double l) {
  const double eps = (l - L0) / L0;
  switch (law.kind) {
    case SpringLawKind::linear: return law.k;
    case SpringLawKind::cubic: return law.k * (1.0 + 3.0 * law.beta * eps * eps);
    case SpringLawKind::exponential: return law.k * std::exp(law.beta * eps);
  }
  return 0.0;
}

const char* to_string(SpringLawKind kind) {
  switch (kind) {
    case SpringLawKind::linear: return "linear";
    case SpringLawKind::cubic: return "cubic";
    case SpringLawKind::exponential: return "exponential";
  }
  return "?";
}

}  // namespace harness
