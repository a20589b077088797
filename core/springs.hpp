// Nonlinear spring laws (docs/scenes.md, "material"). Strain eps = (l - L0)/L0, tension positive:
//   linear       f = k L0 eps
//   cubic        f = k L0 (eps + beta eps^3)
//   exponential  f = k L0 (exp(beta eps) - 1)/beta        (linear as beta -> 0)
// k in N/m, L0 and l in m, f in N, energy in J. Energy is the integral of f over l from L0,
// so f = dE/dl exactly (tested by finite differences).
#pragma once

#include "core/device/hd.hpp"

#include <cmath>

namespace harness {

enum class SpringLawKind { linear, cubic, exponential };

// The law of one spring: its kind, stiffness k and nonlinearity.
struct SpringLaw {
  SpringLawKind kind = SpringLawKind::linear;
  double k = 0.0;     // N/m
  double beta = 0.0;  // dimensionless nonlinearity, >= 0
};

// expm1 as the force laws evaluate it: for |x| <= kExpm1Direct the halving polynomial below, in
// IEEE + - * only, so that a SIMD lane computes exactly what a scalar does, on every instruction
// set and every processor; beyond it (strains far outside the tissue's range) std::expm1. One
// value and a batch give the same bits.
constexpr double kExpm1Direct = 2.0;
// 1/n! for n = 2..13.
constexpr double kExpm1Coef[12] = {1.0 / 2,         1.0 / 6,          1.0 / 24,          1.0 / 120,
                                   1.0 / 720,       1.0 / 5040,       1.0 / 40320,       1.0 / 362880,
                                   1.0 / 3628800,   1.0 / 39916800,   1.0 / 479001600,   1.0 / 6227020800};
// expm1(x) for |x| <= kExpm1Direct over any number type T with IEEE + - * (a double or a lane
// type of core/simd): y = x / 8 (exact), e = y + y^2 q(y) with q(y) = 1/2! + y/3! + ... +
// y^11/13! (for |y| <= 1/4 the truncated terms are below 3e-18 of e) by Estrin's scheme (pairs,
// then powers y^2, y^4, y^8: a dependency chain of depth 5, not Horner's 11, so that the SIMD
// lanes' latency overlaps), then expm1(2y) = e (e + 2) three times. Relative error within a few
// units in the last place, also as x -> 0. c[k] = kExpm1Coef[k] as T, eighth = 0.125, two = 2.
template <class T>
HARNESS_HD inline T expm1_halving(const T& x, const T* c, const T& eighth, const T& two) {
  const T y = x * eighth;
  const T y2 = y * y;
  const T y4 = y2 * y2;
  const T y8 = y4 * y4;
  const T p0 = c[0] + c[1] * y, p1 = c[2] + c[3] * y, p2 = c[4] + c[5] * y;
  const T p3 = c[6] + c[7] * y, p4 = c[8] + c[9] * y, p5 = c[10] + c[11] * y;
  const T q0 = p0 + p1 * y2, q1 = p2 + p3 * y2, q2 = p4 + p5 * y2;
  const T q = (q0 + q1 * y4) + q2 * y8;
  T e = y + y2 * q;
  e = e * (e + two);
  e = e * (e + two);
  e = e * (e + two);
  return e;
}
double spring_expm1(double x);
// out[i] = spring_expm1(x[i]) for i < n.
void spring_expm1_batch(const double* x, double* out, int n);

// Tension (N) of a spring of rest length L0 stretched to length l.
double spring_tension(const SpringLaw& law, double L0, double l);
// Tension over length, t / l (N/m): end i of a spring feels c (x_j - x_i). Every force path
// (the kernels of core/simd, the scalar definitions in tests) evaluates exactly these expressions,
// with s = l - L0 and the reciprocals r = 1 / l, q = 1 / L0 (correctly rounded divisions: one per
// spring in the force pass, 1 / L0 kept with the spring), eps = s q, x = beta eps:
//   linear       c = k s r
//   cubic        c = k s (L0 L0 + beta s s) (q q) r
//   exponential  c = k L0 expm1(x) (1 / beta) r, or k s (1 + x/2) r when |x| < 1e-8
//                (expm1 = spring_expm1)
// (the tension over the length up to rounding: k L0 eps = k s, eps^2 = s^2 q^2 and
// k L0 eps expm1(x)/x = k L0 expm1(x) / beta).
double spring_force_per_length(const SpringLaw& law, double L0, double l);

// The laws of spring_force_per_length over any number type T with IEEE + - * (a double, or a lane
// type of the SIMD kernels, each of whose lanes then does these operations).
template <class T>
HARNESS_HD inline T linear_law(const T& k, const T& s, const T& r) {
  return k * s * r;
}
template <class T>
HARNESS_HD inline T cubic_law(const T& k, const T& beta, const T& L0, const T& s, const T& q, const T& r) {
  return k * s * (L0 * L0 + beta * s * s) * (q * q) * r;
}
template <class T>
HARNESS_HD inline T exponential_near(const T& k, const T& s, const T& x, const T& one, const T& half, const T& r) {
  return k * s * (one + half * x) * r;
}
template <class T>
HARNESS_HD inline T exponential_far(const T& k, const T& L0, const T& em1, const T& inv_beta, const T& r) {
  return k * L0 * em1 * inv_beta * r;
}
// The tangent stiffness over l^2 (the stability guard's rows), the same way: linear |k| r r;
// cubic |k (L0 L0 + 3 beta s s)| (q q) (r r); exponential |k (1 + expm1(x))| r r (as T = the
// value inside |.|, the caller takes the absolute value).
template <class T>
HARNESS_HD inline T cubic_tangent(const T& k, const T& beta, const T& L0, const T& s, const T& q, const T& three) {
  return k * (L0 * L0 + three * beta * s * s) * (q * q);
}
// The exponential law's argument x = beta eps = beta ((l - L0) q).
inline double exponential_arg(const SpringLaw& law, double L0, double l) { return law.beta * ((l - L0) * (1.0 / L0)); }

// Stored energy (J).
double spring_energy(const SpringLaw& law, double L0, double l);
// The energies of spring_energy over any number type T (the force pass's lanes evaluate them
// beside the force), eps = (l - L0) / L0, kL2 = k L0 L0:
//   linear       0.5 kL2 eps^2
//   cubic        kL2 (0.5 eps^2 + 0.25 beta eps^4)
//   exponential  kL2 eps^2 g(x), x = beta eps, g(x) = (e^x - 1 - x) / x^2: (em1 - x) / x^2 for
//                |x| >= 1e-3, else its series 1/2 + x/6 + x^2/24 + x^3/120 (the direct form cancels)
template <class T>
HARNESS_HD inline T linear_energy(const T& kL2, const T& eps, const T& half) {
  return half * kL2 * eps * eps;
}
template <class T>
HARNESS_HD inline T cubic_energy(const T& kL2, const T& beta, const T& eps, const T& half, const T& quarter) {
  return kL2 * (half * eps * eps + quarter * beta * eps * eps * eps * eps);
}
template <class T>
HARNESS_HD inline T exp_energy_series(const T& x, const T& half, const T& six, const T& c24, const T& c120) {
  return half + x / six + x * x / c24 + x * x * x / c120;
}
template <class T>
HARNESS_HD inline T exp_energy_direct(const T& x, const T& em1) {
  return (em1 - x) / (x * x);
}
// Tangent stiffness df/dl (N/m) at length l.
double spring_tangent(const SpringLaw& law, double L0, double l);
// Both at once, one exponential for the exponential law (the implicit step's Jacobian), equal to
// spring_tension and spring_tangent.
void spring_tension_tangent(const SpringLaw& law, double L0, double l, double& tension, double& tangent);

const char* to_string(SpringLawKind kind);

}  // namespace harness
