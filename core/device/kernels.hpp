// The step's kernel bodies, written once for the CPU and the GPU (core/device/README in
// docs/architecture.md, "The step on a GPU"): every function here is HARNESS_HD, takes plain
// pointers (a View: host memory on the CPU executor, device memory on the CUDA one) and an index,
// and does the CPU step's operations in the CPU step's order, so the CPU executor of these bodies
// (host_step.cpp, the ctest gpu_kernels_*) reproduces Simulation::step and the GPU (built with
// -fmad=false: no fused multiply-add, as the CPU build's -ffp-contract=off) computes the same
// numbers wherever its sums are ordered alike:
//   node_forces      one node: each spring it is an end of evaluated as the CPU's force pass
//                    evaluates it at its upper end (core/simd's SpringEvalRun), summed in the
//                    CPU's four interleaved partial sums (SpringSumRun), mass damping, then the
//                    external forces (gravity, pressure from its incident faces in face order,
//                    loads) joined as Simulation::add_forces joins them;
//   drive_node       one driven node's kinematic state for the step (DriversEffect::begin_step);
//   integrate_node   symplectic Euler (integrator.hpp);
//   the contact      per pair and direction: the host's box, the grid's geometry (Initializer),
//                    the grid filled by a counting sort whose lists are then sorted by node (the
//                    lists of VoxelData: increasing node order), each guest node's push (the
//                    voxel detector with the line or the plane rule, or voxel_exact's exact narrow
//                    phase; constant or penalty force), and the pushes applied to every node in
//                    the CPU's push order (each node's reactions sorted by push).
// Atomic adds (atomic_add) are the only operations whose order varies on the GPU; they count, and
// every list they fill is sorted before it is read, so the results never depend on the order.
#pragma once

#include "core/device/hd.hpp"
#include "core/springs.hpp"

#include <cmath>

namespace harness::dev {

using std::atan2;
using std::expm1;
using std::fabs;
using std::floor;
using std::isfinite;
using std::sqrt;

// ---- Small vector arithmetic with Eigen's operation order (dot: (x x + y y) + z z; cross as
// Eigen's cross; a scalar times a vector per component).
struct V3 {
  double x, y, z;
};
HARNESS_HD inline V3 v3(double a, double b, double c) { return V3{a, b, c}; }
HARNESS_HD inline V3 operator+(V3 a, V3 b) { return V3{a.x + b.x, a.y + b.y, a.z + b.z}; }
HARNESS_HD inline V3 operator-(V3 a, V3 b) { return V3{a.x - b.x, a.y - b.y, a.z - b.z}; }
HARNESS_HD inline V3 operator-(V3 a) { return V3{-a.x, -a.y, -a.z}; }
HARNESS_HD inline V3 operator*(double s, V3 a) { return V3{s * a.x, s * a.y, s * a.z}; }
HARNESS_HD inline V3 operator*(V3 a, double s) { return V3{a.x * s, a.y * s, a.z * s}; }
HARNESS_HD inline V3 operator/(V3 a, double s) { return V3{a.x / s, a.y / s, a.z / s}; }
HARNESS_HD inline double dot(V3 a, V3 b) { return (a.x * b.x + a.y * b.y) + a.z * b.z; }
HARNESS_HD inline double sqnorm(V3 a) { return dot(a, a); }
HARNESS_HD inline double norm(V3 a) { return sqrt(dot(a, a)); }
HARNESS_HD inline V3 cross(V3 a, V3 b) {
  return V3{a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
HARNESS_HD inline bool finite3(V3 a) { return isfinite(a.x) && isfinite(a.y) && isfinite(a.z); }
HARNESS_HD inline V3 load3(const double* p, int i) { return V3{p[3 * i], p[3 * i + 1], p[3 * i + 2]}; }
HARNESS_HD inline void store3(double* p, int i, V3 a) { p[3 * i] = a.x, p[3 * i + 1] = a.y, p[3 * i + 2] = a.z; }
HARNESS_HD inline double dmin(double a, double b) { return b < a ? b : a; }
HARNESS_HD inline double dmax(double a, double b) { return a < b ? b : a; }
HARNESS_HD inline int imin(int a, int b) { return b < a ? b : a; }
HARNESS_HD inline int imax(int a, int b) { return a < b ? b : a; }

// An atomic add on the GPU, a plain one on the CPU executor (one thread). Returns the old value.
HARNESS_HD inline int atomic_add(int* p, int v) {
#if defined(__CUDA_ARCH__)
  return atomicAdd(p, v);
#else
  const int o = *p;
  *p = o + v;
  return o;
#endif
}

// directions.hpp's unit_or_zero (with its rescaling when |a| overflows).
HARNESS_HD inline V3 unit_or_zero(V3 a) {
  const double n = norm(a);
  if (!(n > 0.0) || !isfinite(n)) {
    const double s = dmax(dmax(fabs(a.x), fabs(a.y)), fabs(a.z));
    if (!(s > 0.0) || !isfinite(s)) return V3{0.0, 0.0, 0.0};
    const V3 b = a / s;
    return b / norm(b);
  }
  const V3 u = a / n;
  return finite3(u) ? u : V3{0.0, 0.0, 0.0};
}

// ---- Node state and the springs (the CPU's SpringGather, spring_forces.hpp).
enum NodeKind : unsigned char { kFree = 0, kPinned = 1, kDriven = 2 };  // world.hpp's Kinematic

struct Law {  // a body's spring law and dashpot (SpringGather::Run)
  int kind;   // SpringLawKind
  double beta, inv_beta, damping;
};

// The springs, node-centric (built from SpringGather, spring_forces.hpp): node i's half-edges
// [start[i], split[i]) are its upper ones (to a higher node: d = x_other - x_i) and
// [split[i], start[i + 1]) its lower ones (other = the spring's upper end: d = x_i - x_other), each
// list in SpringGather's order, with the spring's rest length and stiffness beside it. Each node
// evaluates every spring it is an end of (a spring twice, at its two ends, by the same operations
// on the same operands: the same bits), so one pass over the nodes makes the forces with no
// intermediate box in memory; 1 / L0 is recomputed (a correctly rounded division: SpringGather's
// value).
struct SpringsView {
  const int* start = nullptr;  // n + 1
  const int* split = nullptr;  // n
  const int* other = nullptr;
  const double* rest = nullptr;
  const double* stiff = nullptr;
  const int* law = nullptr;    // per node: its body's law
  const Law* laws = nullptr;
};

// The spring's force law (springs.hpp's spring_force_per_length in the force pass's operations).
HARNESS_HD inline double tension_over_length(const Law& L, double k, double L0, double q, double l, double r) {
  const double s = l - L0;
  if (L.kind == static_cast<int>(SpringLawKind::linear)) return linear_law(k, s, r);
  if (L.kind == static_cast<int>(SpringLawKind::cubic)) return cubic_law(k, L.beta, L0, s, q, r);
  const double eps = s * q;
  const double x = L.beta * eps;
  if (fabs(x) < 1e-8) return exponential_near(k, s, x, 1.0, 0.5, r);
  double em1;
  if (fabs(x) <= kExpm1Direct) {
    const double c[12] = {1.0 / 2,       1.0 / 6,        1.0 / 24,        1.0 / 120,
                          1.0 / 720,     1.0 / 5040,     1.0 / 40320,     1.0 / 362880,
                          1.0 / 3628800, 1.0 / 39916800, 1.0 / 479001600, 1.0 / 6227020800};
    em1 = expm1_halving(x, c, 0.125, 2.0);
  } else {
    em1 = expm1(x);
  }
  return exponential_far(k, L0, em1, L.inv_beta, r);
}

// One spring, seen from its upper end (core/simd's SpringEvalRun): d = x_j - x_i, u = v_j - v_i;
// F = c d (springs), G = s d (dashpots), both 0 d for a zero length.
HARNESS_HD inline void spring_force(const Law& L, double k, double L0, const double d[3], const double u[3], bool springs,
                                    bool dashpots, double F[3], double G[3]) {
  const double l2 = (d[0] * d[0] + d[1] * d[1]) + d[2] * d[2];
  const bool zero_length = l2 <= 0.0;
  const double l = sqrt(l2);
  const double rl = 1.0 / l;
  if (springs) {
    double c = tension_over_length(L, k, L0, 1.0 / L0, l, rl);
    if (zero_length) c = 0.0;
    F[0] = d[0] * c, F[1] = d[1] * c, F[2] = d[2] * c;
  }
  if (dashpots) {
    double s = L.damping * ((u[0] * d[0] + u[1] * d[1]) + u[2] * d[2]) * (rl * rl);
    if (zero_length) s = 0.0;
    G[0] = d[0] * s, G[1] = d[1] * s, G[2] = d[2] * s;
  }
}

// Partial sum q % 4 of a node's springs and dashpots (core/simd's SpringSumRun): P[q] holds
// x y z of the springs, then x y z of the dashpots.
template <int Q>
HARNESS_HD inline void half_edge(const SpringsView& S, const Law& L, const double* x, const double* v, int i, int h,
                                 bool upper, bool springs, bool dashpots, double (&P)[4][6]) {
  const int j = S.other[h];
  double d[3], u[3] = {0.0, 0.0, 0.0}, F[3] = {0.0, 0.0, 0.0}, G[3] = {0.0, 0.0, 0.0};
  const int a = upper ? j : i, b = upper ? i : j;  // d = x_a - x_b: the upper end's view
  for (int k = 0; k < 3; ++k) d[k] = x[3 * a + k] - x[3 * b + k];
  if (dashpots)
    for (int k = 0; k < 3; ++k) u[k] = v[3 * a + k] - v[3 * b + k];
  spring_force(L, S.stiff[h], S.rest[h], d, u, springs, dashpots, F, G);
  for (int k = 0; k < 3; ++k) {
    if (upper) {
      P[Q][k] += F[k];
      P[Q][3 + k] += G[k];
    } else {
      P[Q][k] += 0.0 - F[k];
      P[Q][3 + k] += 0.0 - G[k];
    }
  }
}

template <bool Upper>
HARNESS_HD inline void half_edges(const SpringsView& S, const Law& L, const double* x, const double* v, int i, int b, int e,
                                  bool springs, bool dashpots, double (&P)[4][6]) {
  int h = b;
  for (; h + 4 <= e; h += 4) {
    half_edge<0>(S, L, x, v, i, h, Upper, springs, dashpots, P);
    half_edge<1>(S, L, x, v, i, h + 1, Upper, springs, dashpots, P);
    half_edge<2>(S, L, x, v, i, h + 2, Upper, springs, dashpots, P);
    half_edge<3>(S, L, x, v, i, h + 3, Upper, springs, dashpots, P);
  }
  if (h < e) half_edge<0>(S, L, x, v, i, h, Upper, springs, dashpots, P);
  if (h + 1 < e) half_edge<1>(S, L, x, v, i, h + 1, Upper, springs, dashpots, P);
  if (h + 2 < e) half_edge<2>(S, L, x, v, i, h + 2, Upper, springs, dashpots, P);
}

// The external forces' parameters (gravity, pressure, loads) and the node-level effects.
struct NodeView {
  int n = 0;
  double* x = nullptr;
  double* v = nullptr;
  double* f = nullptr;
  const double* m = nullptr;
  const double* inv_m = nullptr;
  unsigned char* kind = nullptr;  // NodeKind
  double* kin_v = nullptr;
  const double* mass_damping = nullptr;  // per node: the body's mass_damping (0: none)
  bool springs = false, dashpots = false, damping = false;
  bool external = false;  // some external effect is built: f_ext joins f
  bool gravity = false;
  double g[3] = {0.0, 0.0, 0.0};
  // Pressure: per node the incident faces (CSR over global nodes, face order), a face's three
  // global vertices and its body's pressure index; per pressure body its ramp.
  const int* pf_start = nullptr;
  const int* pf_face = nullptr;
  const int* face_v = nullptr;  // 3 per face
  const int* face_p = nullptr;  // pressure index of the face's body
  const double* p_from = nullptr;
  const double* p_to = nullptr;
  const int* p_ramp = nullptr;
  // Loads: per node the loads that act on it (CSR, load order); per load its force, node count, ramp.
  const int* ld_start = nullptr;
  const int* ld_load = nullptr;
  const double* ld_force = nullptr;  // 3 per load
  const int* ld_count = nullptr;
  const int* ld_ramp = nullptr;
};

// PressureEffect's ramp (pressure.cpp's ramp_pressure).
HARNESS_HD inline double ramp_pressure(double from, double to, int ramp_steps, int step) {
  if (ramp_steps <= 0 || step >= ramp_steps) return to;
  const double a = static_cast<double>(imax(step, 0)) / ramp_steps;
  return from + (to - from) * a;
}

// Node i's force before contact: ((0 + springs) + dashpots) - mass damping, then + f_ext.
HARNESS_HD inline void node_forces(const SpringsView& S, const NodeView& N, int step, int i) {
  double se[3] = {0.0, 0.0, 0.0}, sd[3] = {0.0, 0.0, 0.0};
  if (N.springs || N.dashpots) {
    double P[4][6] = {};
    const Law& L = S.laws[S.law[i]];
    half_edges<true>(S, L, N.x, N.v, i, S.start[i], S.split[i], N.springs, N.dashpots, P);
    half_edges<false>(S, L, N.x, N.v, i, S.split[i], S.start[i + 1], N.springs, N.dashpots, P);
    for (int k = 0; k < 3; ++k) {
      se[k] = (P[0][k] + P[1][k]) + (P[2][k] + P[3][k]);
      sd[k] = (P[0][3 + k] + P[1][3 + k]) + (P[2][3 + k] + P[3][3 + k]);
    }
  }
  double f[3] = {0.0, 0.0, 0.0};
  for (int k = 0; k < 3; ++k) {
    if (N.springs) f[k] += se[k];
    if (N.dashpots) f[k] += sd[k];
  }
  if (N.damping) {
    const double a = N.mass_damping[i];
    if (a != 0.0) {
      const double am = a * N.m[i];
      for (int k = 0; k < 3; ++k) f[k] -= am * N.v[3 * i + k];
    }
  }
  if (N.external) {
    double e[3] = {0.0, 0.0, 0.0};
    if (N.gravity)
      for (int k = 0; k < 3; ++k) e[k] += N.m[i] * N.g[k];
    if (N.pf_start) {
      for (int t = N.pf_start[i]; t < N.pf_start[i + 1]; ++t) {
        const int face = N.pf_face[t], pi = N.face_p[face];
        const double s = ramp_pressure(N.p_from[pi], N.p_to[pi], N.p_ramp[pi], step) / 6.0;
        const V3 a = load3(N.x, N.face_v[3 * face]);
        const V3 fn = s * cross(load3(N.x, N.face_v[3 * face + 1]) - a, load3(N.x, N.face_v[3 * face + 2]) - a);
        e[0] += fn.x, e[1] += fn.y, e[2] += fn.z;
      }
    }
    if (N.ld_start) {
      for (int t = N.ld_start[i]; t < N.ld_start[i + 1]; ++t) {
        const int L = N.ld_load[t];
        const double ramp = N.ld_ramp[L] <= 0 ? 1.0 : dmin(1.0, static_cast<double>(imax(step, 0)) / N.ld_ramp[L]);
        const double s = ramp / static_cast<double>(N.ld_count[L]);
        for (int k = 0; k < 3; ++k) e[k] += s * N.ld_force[3 * L + k];
      }
    }
    for (int k = 0; k < 3; ++k) f[k] += e[k];
  }
  for (int k = 0; k < 3; ++k) N.f[3 * i + k] = f[k];
}

// Drivers (DriversEffect::begin_step) for driver node d of dr_nodes: the last active driver that
// lists it moves it; none active: a node still driven is released with its velocity.
struct DriversView {
  int nodes = 0;
  const int* node = nullptr;    // unique driver nodes
  const int* start = nullptr;   // per driver node, its drivers (CSR, driver order)
  const int* driver = nullptr;
  const int* from = nullptr;    // per driver
  const int* to = nullptr;
  const double* vel = nullptr;  // 3 per driver
};
HARNESS_HD inline void drive_node(const DriversView& D, const NodeView& N, int step, int d) {
  const int i = D.node[d];
  if (N.kind[i] == kPinned) return;
  int active = -1;
  for (int t = D.start[d]; t < D.start[d + 1]; ++t) {
    const int k = D.driver[t];
    if (step >= D.from[k] && (D.to[k] < 0 || step <= D.to[k])) active = k;
  }
  if (active >= 0) {
    N.kind[i] = kDriven;
    for (int c = 0; c < 3; ++c) N.kin_v[3 * i + c] = D.vel[3 * active + c], N.v[3 * i + c] = D.vel[3 * active + c];
  } else if (N.kind[i] == kDriven) {
    N.kind[i] = kFree;
    for (int c = 0; c < 3; ++c) N.kin_v[3 * i + c] = 0.0;
  }
}

// Symplectic Euler (integrator.hpp); `bad` is set when the node's new state is not finite.
HARNESS_HD inline void integrate_node(const NodeView& N, double h, int i, int* bad) {
  switch (N.kind[i]) {
    case kFree: {
      const double s = h * N.inv_m[i];
      for (int k = 0; k < 3; ++k) N.v[3 * i + k] += s * N.f[3 * i + k];
      for (int k = 0; k < 3; ++k) N.x[3 * i + k] += h * N.v[3 * i + k];
      break;
    }
    case kPinned: break;
    default:
      for (int k = 0; k < 3; ++k) N.x[3 * i + k] += h * N.kin_v[3 * i + k];
  }
  if (!(isfinite(N.x[3 * i]) && isfinite(N.x[3 * i + 1]) && isfinite(N.x[3 * i + 2]) && isfinite(N.v[3 * i]) &&
        isfinite(N.v[3 * i + 1]) && isfinite(N.v[3 * i + 2])))
    *bad = 1;
}

}  // namespace harness::dev
