// The voxel_exact detector's narrow-phase geometry (voxel_exact.hpp states the method): the
// closest point of a triangle to a node with its feature and barycentric weights (a collapsed
// triangle through its edges), and lower bounds of a node's distance to candidate triangles from
// their bounding boxes, two boxes per vector operation. Every lane does the scalar operation:
// the results are the scalar loop's, bit for bit.
#pragma once

#include "core/geometry.hpp"
#include "core/types.hpp"

#include <cmath>
#include <cstring>
#include <limits>

namespace harness::voxel_exact_geometry {

// The closest point q of triangle (a, b, c) to p (Ericson, Real-Time Collision Detection 5.1.5),
// with its feature (voxel_exact.hpp) and barycentric weights. False for a collapsed triangle
// (a division without a finite result): the caller then takes its edges.
inline bool closest_feature(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, Vec3& q, double wt[3],
                            int& feature) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) {
    q = a, wt[0] = 1, wt[1] = 0, wt[2] = 0, feature = 0;
    return true;
  }
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) {
    q = b, wt[0] = 0, wt[1] = 1, wt[2] = 0, feature = 1;
    return true;
  }
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    const double v = d1 / (d1 - d3);
    if (!std::isfinite(v)) return false;
    q = a + ab * v, wt[0] = 1 - v, wt[1] = v, wt[2] = 0, feature = 3;
    return true;
  }
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) {
    q = c, wt[0] = 0, wt[1] = 0, wt[2] = 1, feature = 2;
    return true;
  }
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    const double w = d2 / (d2 - d6);
    if (!std::isfinite(w)) return false;
    q = a + ac * w, wt[0] = 1 - w, wt[1] = 0, wt[2] = w, feature = 5;
    return true;
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    if (!std::isfinite(w)) return false;
    q = b + (c - b) * w, wt[0] = 0, wt[1] = 1 - w, wt[2] = w, feature = 4;
    return true;
  }
  const double sum = va + vb + vc;  // |ab x ac|^2 for a proper triangle
  if (!(sum > 0.0)) return false;
  const double denom = 1.0 / sum;
  const double v = vb * denom, w = vc * denom;
  if (!std::isfinite(v) || !std::isfinite(w)) return false;
  q = a + ab * v + ac * w, wt[0] = 1 - v - w, wt[1] = v, wt[2] = w, feature = VoxelExactDetector::kInterior;
  return true;
}

// A collapsed triangle: the closest point of its three edges.
inline void closest_on_edges(const Vec3& p, const Vec3* v, Vec3& q, double wt[3], int& feature) {
  double best = std::numeric_limits<double>::infinity();
  q = v[0], wt[0] = 1, wt[1] = 0, wt[2] = 0, feature = 0;
  for (int k = 0; k < 3; ++k) {
    const Vec3 &P = v[k], &Q = v[(k + 1) % 3];
    const Vec3 e = Q - P;
    const double l2 = e.squaredNorm();
    double t = l2 > 0.0 ? (p - P).dot(e) / l2 : 0.0;
    t = std::isfinite(t) ? std::clamp(t, 0.0, 1.0) : 0.0;
    const Vec3 s = P + t * e;
    const double d2 = (s - p).squaredNorm();
    if (d2 < best) {
      best = d2;
      q = s;
      wt[0] = wt[1] = wt[2] = 0.0;
      wt[k] = 1.0 - t;
      wt[(k + 1) % 3] += t;
      feature = t == 0.0 ? k : t == 1.0 ? (k + 1) % 3 : 3 + k;
    }
  }
}

// Two doubles in one vector (GCC / Clang vector extensions: one SSE2 register on x86-64, NEON
// on arm64); every lane does the scalar operation, so the results are the scalar loop's bit for
// bit.
typedef double Lanes __attribute__((vector_size(16)));

// out[i] = the squared distance from x to box i (rows lo x, y, z, hi x, y, z of `stride` doubles
// each), for i < m rounded up to an even count (the rows hold that many: the extra lane is
// computed and ignored).
inline void box_bounds(const double* box, int stride, int m, const Vec3& x, double* out) {
  const Lanes x0 = {x[0], x[0]}, x1 = {x[1], x[1]}, x2 = {x[2], x[2]};
  const Lanes zero = {0.0, 0.0};
  for (int i = 0; i < m; i += 2) {
    Lanes l[3], h[3];
    for (int d = 0; d < 3; ++d) {
      std::memcpy(&l[d], box + d * stride + i, sizeof(Lanes));
      std::memcpy(&h[d], box + (3 + d) * stride + i, sizeof(Lanes));
    }
    Lanes dx = l[0] - x0, ex = x0 - h[0];
    Lanes dy = l[1] - x1, ey = x1 - h[1];
    Lanes dz = l[2] - x2, ez = x2 - h[2];
    dx = dx > ex ? dx : ex;
    dy = dy > ey ? dy : ey;
    dz = dz > ez ? dz : ez;
    dx = dx > zero ? dx : zero;
    dy = dy > zero ? dy : zero;
    dz = dz > zero ? dz : zero;
    const Lanes b = dx * dx + dy * dy + dz * dz;
    std::memcpy(out + i, &b, sizeof(Lanes));
  }
}

// The same for one box (lo, hi), scalar.
inline double box_bound(const Vec3& lo, const Vec3& hi, const Vec3& x) {
  double d2 = 0.0;
  for (int a = 0; a < 3; ++a) {
    double d = lo[a] - x[a], e = x[a] - hi[a];
    d = d > e ? d : e;
    d = d > 0.0 ? d : 0.0;
    d2 += d * d;
  }
  return d2;
}

}  // namespace harness::voxel_exact_geometry
