// The closest point of a triangle to a point, with its feature and barycentric weights
// (Ericson, Real-Time Collision Detection 5.1.5), and of a collapsed triangle's edges: one body
// for voxel_exact's narrow phase on the CPU (voxel_exact_geometry.hpp, through Vec3 <-> V3) and on
// a device (exact_kernels.hpp). V3's arithmetic is Eigen's operation order (kernels.hpp), so the
// CPU's results are those of Eigen's expressions, bit for bit.
#pragma once

#include "core/device/kernels.hpp"

namespace harness::dev {

// The feature of a point inside the triangle (VoxelExactDetector::kInterior); 0-2 the vertices,
// 3, 4, 5 the edges ab, bc, ca.
constexpr int kInteriorFeature = 6;

// The closest point q of triangle (a, b, c) to p, its feature and weights. False for a collapsed
// triangle (a division without a finite result): the caller then takes its edges.
HARNESS_HD inline bool closest_feature(V3 p, V3 a, V3 b, V3 c, V3& q, double wt[3], int& feature) {
  const V3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return q = a, wt[0] = 1, wt[1] = 0, wt[2] = 0, feature = 0, true;
  const V3 bp = p - b;
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return q = b, wt[0] = 0, wt[1] = 1, wt[2] = 0, feature = 1, true;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    const double v = d1 / (d1 - d3);
    if (!isfinite(v)) return false;
    return q = a + ab * v, wt[0] = 1 - v, wt[1] = v, wt[2] = 0, feature = 3, true;
  }
  const V3 cp = p - c;
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return q = c, wt[0] = 0, wt[1] = 0, wt[2] = 1, feature = 2, true;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    const double w = d2 / (d2 - d6);
    if (!isfinite(w)) return false;
    return q = a + ac * w, wt[0] = 1 - w, wt[1] = 0, wt[2] = w, feature = 5, true;
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    if (!isfinite(w)) return false;
    return q = b + (c - b) * w, wt[0] = 0, wt[1] = 1 - w, wt[2] = w, feature = 4, true;
  }
  const double sum = va + vb + vc;
  if (!(sum > 0.0)) return false;
  const double denom = 1.0 / sum;
  const double v = vb * denom, w = vc * denom;
  if (!isfinite(v) || !isfinite(w)) return false;
  q = a + ab * v + ac * w, wt[0] = 1 - v - w, wt[1] = v, wt[2] = w, feature = kInteriorFeature;
  return true;
}
HARNESS_HD inline void closest_on_edges(V3 p, const V3* v, V3& q, double wt[3], int& feature) {
  double best = INFINITY;
  q = v[0], wt[0] = 1, wt[1] = 0, wt[2] = 0, feature = 0;
  for (int k = 0; k < 3; ++k) {
    const V3 P = v[k], Q = v[(k + 1) % 3];
    const V3 e = Q - P;
    const double l2 = sqnorm(e);
    double t = l2 > 0.0 ? dot(p - P, e) / l2 : 0.0;
    t = isfinite(t) ? dmin(dmax(t, 0.0), 1.0) : 0.0;
    const V3 s = P + t * e;
    const double d2 = sqnorm(s - p);
    if (d2 < best) {
      best = d2, q = s;
      wt[0] = wt[1] = wt[2] = 0.0;
      wt[k] = 1.0 - t;
      wt[(k + 1) % 3] += t;
      feature = t == 0.0 ? k : t == 1.0 ? (k + 1) % 3 : 3 + k;
    }
  }
}

}  // namespace harness::dev
