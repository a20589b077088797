#include "core/springs.hpp"

#include <cmath>

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
  const double s = l - L0;
  switch (law.kind) {
    case SpringLawKind::linear: return law.k * s / l;
    case SpringLawKind::cubic: {
      const double L2 = L0 * L0;
      return law.k * s * (L2 + law.beta * s * s) / (L2 * l);
    }
    case SpringLawKind::exponential: {
      const double x = law.beta * (s / L0);
      if (std::fabs(x) < 1e-8) return law.k * s * (1.0 + 0.5 * x) / l;
      return law.k * L0 * std::expm1(x) / (law.beta * l);
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
