#include "core/world.hpp"

#include "core/parallel.hpp"
#include "core/simd/kernels.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace harness {

void points_bounds(const Points& x, int begin, int end, Vec3& lo, Vec3& hi) {
  const double inf = std::numeric_limits<double>::infinity();
  const int n = std::max(0, end - begin);
  const int T = threads_for(static_cast<std::size_t>(n), 16384);
  double part[64][6];  // per thread: lo xyz, hi xyz
  const int parts = std::min(T, 64);
  const simd::Kernels& kern = simd::kernels();
#pragma omp parallel for num_threads(parts) if(parts > 1) schedule(static, 1)
  for (int t = 0; t < parts; ++t) {
    std::size_t b, e;
    split_range(static_cast<std::size_t>(n), parts, t, b, e);
    for (int a = 0; a < 3; ++a) part[t][a] = inf, part[t][3 + a] = -inf;
    if (e > b) kern.bounds(x[static_cast<std::size_t>(begin) + b].data(), e - b, part[t]);
  }
  lo = Vec3::Constant(inf);
  hi = Vec3::Constant(-inf);
  for (int t = 0; t < parts; ++t)
    for (int a = 0; a < 3; ++a) {
      lo[a] = part[t][a] < lo[a] ? part[t][a] : lo[a];
      hi[a] = hi[a] < part[t][3 + a] ? part[t][3 + a] : hi[a];
    }
  // min and max are exact; only the sign of a zero could depend on the order of the points.
  lo = lo + Vec3::Zero();
  hi = hi + Vec3::Zero();
}

void body_bounds(const World& w, int body, Vec3& lo, Vec3& hi) {
  const Body& b = w.bodies[body];
  points_bounds(w.x, b.begin, b.end, lo, hi);
}

Vec3 vertex_normal(const World& w, int body, int s) {
  const Body& b = w.bodies[body];
  Vec3 n = Vec3::Zero();
  for (int k = b.vf_start[s]; k < b.vf_start[s + 1]; ++k) {
    const Tri& t = b.faces[b.vf_faces[k]];
    const Vec3& a = w.x[b.begin + t[0]];
    n += (w.x[b.begin + t[1]] - a).cross(w.x[b.begin + t[2]] - a);
  }
  return n;
}

double enclosed_volume(const World& w, int body) {
  const Body& b = w.bodies[body];
  double v = 0.0;
  for (const Tri& t : b.faces)
    v += w.x[b.begin + t[0]].dot(w.x[b.begin + t[1]].cross(w.x[b.begin + t[2]]));
  return v / 6.0;
}

double kinetic_energy(const World& w) {
  double e = 0.0;
  for (int i = 0; i < w.num_nodes(); ++i) e += 0.5 * w.m[i] * w.v[i].squaredNorm();
  return e;
}

double mean_rest_length(const World& w, int body) {
  const Body& b = w.bodies[body];
  if (b.spring_end <= b.spring_begin) return 0.0;
  double sum = 0.0;
  for (int k = b.spring_begin; k < b.spring_end; ++k) sum += w.springs.rest[k];
  return sum / (b.spring_end - b.spring_begin);
}

double rest_spring_length(const World& w, int body) {
  const Body& b = w.bodies[body];
  if (b.spring_end > b.spring_begin || b.size() == 0) return mean_rest_length(w, body);
  Vec3 lo, hi;
  body_bounds(w, body, lo, hi);
  return (hi - lo).maxCoeff() / std::cbrt(static_cast<double>(b.size()));
}

double mean_surface_edge(const World& w, int body, const Points& x) {
  const Body& b = w.bodies[body];
  if (b.faces.empty()) return 0.0;
  double sum = 0.0;
  for (const Tri& t : b.faces)
    for (int k = 0; k < 3; ++k) sum += (x[b.begin + t[k]] - x[b.begin + t[(k + 1) % 3]]).norm();
  return sum / (3.0 * static_cast<double>(b.faces.size()));
}

double rest_surface_edge(const World& w, int body) {
  return mean_surface_edge(w, body, w.x0.empty() ? w.x : w.x0);
}

double current_surface_edge(const World& w, int body) { return mean_surface_edge(w, body, w.x); }

}  // namespace harness
