// Nonlinear spring laws (DESIGN.md). Strain eps = (l - L0)/L0, tension positive:
//   linear       f = k L0 eps
//   cubic        f = k L0 (eps + beta eps^3)
//   exponential  f = k L0 (exp(beta eps) - 1)/beta        (linear as beta -> 0)
// k in N/m, L0 and l in m, f in N, energy in J. Energy is the integral of f over l from L0,
// so f = dE/dl exactly (tested by finite differences).
#pragma once

#include <cmath>

namespace harness {

enum class SpringLawKind { linear, cubic, exponential };

// The law of one spring: its kind, stiffness k and nonlinearity.
struct SpringLaw {
  SpringLawKind kind = SpringLawKind::linear;
  double k = 0.0;     // N/m
  double beta = 0.0;  // dimensionless nonlinearity, >= 0
};

// expm1 as the force laws evaluate it: glibc's vector expm1 (libmvec, four lanes, within 1 ulp
// or so of std::expm1) when the build has it and the processor has AVX2, else std::expm1. Every
// lane is computed on its own, so one value and a batch give the same bits: the scatter (in
// batches) and the gathers (one at a time) agree. The choice follows the processor, not the
// kernels' level: HARNESS_ISA=scalar still uses libmvec (core/cpu.hpp).
double spring_expm1(double x);
// out[i] = spring_expm1(x[i]) for i < n.
void spring_expm1_batch(const double* x, double* out, int n);
// out[i] = e^x[i] for i < n, the same way (libmvec's exp, else std::exp).
void spring_exp_batch(const double* x, double* out, int n);

// Tension (N) of a spring of rest length L0 stretched to length l.
double spring_tension(const SpringLaw& law, double L0, double l);
// Tension over length, t / l (N/m): end i of a spring feels c (x_j - x_i). Every force path
// (scatter, gathers, SIMD kernels) evaluates exactly this expression, so they agree to the bit.
// With s = l - L0 and x = beta s / L0 it is one division for the polynomial laws, two for the
// exponential:
//   linear       c = k s / l
//   cubic        c = k s (L0^2 + beta s^2) / (L0^2 l)
//   exponential  c = k L0 expm1(x) / (beta l), or k s (1 + x/2) / l when |x| < 1e-8
//                (expm1 = spring_expm1)
// (the same numbers as t / l up to rounding: k L0 eps = k s, eps^2 = s^2 / L0^2 and
// k L0 eps expm1(x)/x = k L0 expm1(x) / beta).
double spring_force_per_length(const SpringLaw& law, double L0, double l);

// The polynomial laws of spring_force_per_length over any number type T with IEEE + - * /: a
// double, or a lane type of the SIMD kernels (core/simd), each of whose lanes then does these
// operations. The scatter, the gathers, the kernels and spring_force_per_length all evaluate
// these, so they agree to the bit.
template <class T>
inline T linear_law(const T& k, const T& L0, const T& l) {
  return k * (l - L0) / l;
}
template <class T>
inline T cubic_law(const T& k, const T& beta, const T& L0, const T& l) {
  const T s = l - L0, L2 = L0 * L0;
  return k * s * (L2 + beta * s * s) / (L2 * l);
}
inline double linear_per_length(const SpringLaw& law, double L0, double l) { return linear_law(law.k, L0, l); }
inline double cubic_per_length(const SpringLaw& law, double L0, double l) {
  return cubic_law(law.k, law.beta, L0, l);
}
// The exponential law's argument x = beta (l - L0) / L0, and the law given x and
// em1 = spring_expm1(x) (a loop may evaluate the expm1 of many springs at once).
inline double exponential_arg(const SpringLaw& law, double L0, double l) { return law.beta * ((l - L0) / L0); }
inline double exponential_per_length(const SpringLaw& law, double L0, double l, double x, double em1) {
  if (std::fabs(x) < 1e-8) return law.k * (l - L0) * (1.0 + 0.5 * x) / l;
  return law.k * L0 * em1 / (law.beta * l);
}
// Stored energy (J).
double spring_energy(const SpringLaw& law, double L0, double l);
// Tangent stiffness df/dl (N/m) at length l.
double spring_tangent(const SpringLaw& law, double L0, double l);

const char* to_string(SpringLawKind kind);

}  // namespace harness
