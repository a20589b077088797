#include "core/springs.hpp"

#include <cmath>

namespace harness {

namespace {
// (exp(x) - 1 - x) / x^2, accurate near 0 where the direct formula cancels.
double exp_energy_kernel(double x) {
  if (std::fabs(x) < 1e-3) return exp_energy_series(x, 0.5, 6.0, 24.0, 120.0);
  return exp_energy_direct(x, spring_expm1(x));
}
// expm1(x)/x, accurate near 0.
double expm1_over_x(double x) {
  if (std::fabs(x) < 1e-8) return 1.0 + 0.5 * x;
  return spring_expm1(x) / x;
}
}  // namespace

double spring_expm1(double x) {
  if (!(std::fabs(x) <= kExpm1Direct)) return std::expm1(x);  // (NaN too)
  return expm1_halving(x, kExpm1Coef, 0.125, 2.0);
}

void spring_expm1_batch(const double* x, double* out, int n) {
  for (int i = 0; i < n; ++i) out[i] = spring_expm1(x[i]);
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
  const double s = l - L0, r = 1.0 / l, q = 1.0 / L0;
  switch (law.kind) {
    case SpringLawKind::linear: return linear_law(law.k, s, r);
    case SpringLawKind::cubic: return cubic_law(law.k, law.beta, L0, s, q, r);
    case SpringLawKind::exponential: {
      const double x = law.beta * (s * q);
      if (std::fabs(x) < 1e-8) return exponential_near(law.k, s, x, 1.0, 0.5, r);
      return exponential_far(law.k, L0, spring_expm1(x), 1.0 / law.beta, r);
    }
  }
  return 0.0;
}

double spring_energy(const SpringLaw& law, double L0, double l) {
  const double eps = (l - L0) * (1.0 / L0);
  const double kL2 = law.k * L0 * L0;
  switch (law.kind) {
    case SpringLawKind::linear: return linear_energy(kL2, eps, 0.5);
    case SpringLawKind::cubic: return cubic_energy(kL2, law.beta, eps, 0.5, 0.25);
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
    case SpringLawKind::exponential: return law.k * (1.0 + spring_expm1(law.beta * eps));
  }
  return 0.0;
}

void spring_tension_tangent(const SpringLaw& law, double L0, double l, double& tension, double& tangent) {
  if (law.kind != SpringLawKind::exponential) {
    tension = spring_tension(law, L0, l);
    tangent = spring_tangent(law, L0, l);
    return;
  }
  const double eps = (l - L0) / L0;
  const double x = law.beta * eps;
  const double em1 = spring_expm1(x);  // once for both
  tension = law.k * L0 * eps * (std::fabs(x) < 1e-8 ? 1.0 + 0.5 * x : em1 / x);
  tangent = law.k * (1.0 + em1);
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
