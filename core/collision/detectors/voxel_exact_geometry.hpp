// The voxel_exact detector's narrow-phase geometry (voxel_exact.hpp states the method): the
// closest point of a triangle to a node with its feature and barycentric weights (a collapsed
// triangle through its edges; the body shared with the device), and lower bounds of a node's distance to candidate triangles from
// their bounding boxes, two boxes per vector operation. Every lane does the scalar operation:
// the results are the scalar loop's, bit for bit.
#pragma once

#include "core/device/closest_kernels.hpp"
#include "core/geometry.hpp"
#include "core/types.hpp"

#include <cmath>
#include <cstring>
#include <limits>

namespace harness::voxel_exact_geometry {

// The closest point q of triangle (a, b, c) to p, with its feature (voxel_exact.hpp) and
// barycentric weights; false for a collapsed triangle (the caller then takes its edges). The one
// body is the device's (core/device/closest_kernels.hpp: Eigen's operation order, so these are
// the Eigen expressions' results bit for bit).
inline dev::V3 to_v3(const Vec3& a) { return dev::V3{a[0], a[1], a[2]}; }
inline bool closest_feature(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, Vec3& q, double wt[3],
                            int& feature) {
  dev::V3 r;
  if (!dev::closest_feature(to_v3(p), to_v3(a), to_v3(b), to_v3(c), r, wt, feature)) return false;
  q = Vec3(r.x, r.y, r.z);
  return true;
}
static_assert(dev::kInteriorFeature == VoxelExactDetector::kInterior);

// A collapsed triangle: the closest point of its three edges.
inline void closest_on_edges(const Vec3& p, const Vec3* v, Vec3& q, double wt[3], int& feature) {
  const dev::V3 t[3] = {to_v3(v[0]), to_v3(v[1]), to_v3(v[2])};
  dev::V3 r;
  dev::closest_on_edges(to_v3(p), t, r, wt, feature);
  q = Vec3(r.x, r.y, r.z);
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
