#include "core/world.hpp"

#include <limits>

namespace harness {

void body_bounds(const World& w, int body, Vec3& lo, Vec3& hi) {
  const Body& b = w.bodies[body];
  lo = Vec3::Constant(std::numeric_limits<double>::infinity());
  hi = -lo;
  for (int i = b.begin; i < b.end; ++i) {
    lo = lo.cwiseMin(w.x[i]);
    hi = hi.cwiseMax(w.x[i]);
  }
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

double mean_rest_length(const World& w, int body) {
  const Body& b = w.bodies[body];
  if (b.spring_end <= b.spring_begin) return 0.0;
  double sum = 0.0;
  for (int k = b.spring_begin; k < b.spring_end; ++k) sum += w.springs.rest[k];
  return sum / (b.spring_end - b.spring_begin);
}

double mean_surface_edge(const World& w, int body, const Points& x) {
  const Body& b = w.bodies[body];
  if (b.faces.empty()) return 0.0;
  double sum = 0.0;
  for (const Tri& t : b.faces)
    for (int k = 0; k < 3; ++k) sum += (x[b.begin + t[k]] - x[b.begin + t[(k + 1) % 3]]).norm();
  return sum / (3.0 * static_cast<double>(b.faces.size()));
}

}  // namespace harness
