#include "core/collision/detectors/triangles.hpp"

#include "core/geometry.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <utility>

namespace harness {

int triangle_vertices_nearest_first(const World& w, int host_begin, const Tri& t, const Vec3& p,
                                    int k, int* out) {
  if (k <= 0) return 0;
  std::array<int, 3> g{host_begin + t[0], host_begin + t[1], host_begin + t[2]};
  std::array<double, 3> d{};
  for (int j = 0; j < 3; ++j) d[j] = (w.x[g[j]] - p).squaredNorm();
  std::array<int, 3> order{0, 1, 2};
  std::sort(order.begin(), order.end(), [&](int i, int j) { return d[i] < d[j] || (d[i] == d[j] && g[i] < g[j]); });
  const int n = std::min(k, 3);
  for (int j = 0; j < n; ++j) out[j] = g[order[j]];
  return n;
}

bool face_normal(const World& w, int begin, const Tri& t, Vec3& n) {
  const Vec3& a = w.x[begin + t[0]];
  const Vec3 c = (w.x[begin + t[1]] - a).cross(w.x[begin + t[2]] - a);
  const double len = c.norm();
  if (!(len > 0.0) || !std::isfinite(len)) return false;
  n = c / len;
  return true;
}

bool triangle_contact_point(const World& w, int begin, const Tri& t, const Vec3& x, ContactPoint& out, bool inside) {
  const Vec3 &a = w.x[begin + t[0]], &b = w.x[begin + t[1]], &c = w.x[begin + t[2]];
  const Vec3 p = closest_on_triangle(x, a, b, c);
  barycentric(p, a, b, c, out.weight);
  for (int k = 0; k < 3; ++k) out.hosts[k] = begin + t[k];
  const Vec3 d = p - x;
  const double len = d.norm();
  Vec3 fn;
  if (!face_normal(w, begin, t, fn)) return false;
  const bool behind = inside || d.dot(fn) > 0.0;
  // Inside, the nearest point lies outward of the node; on the face (or in front of it), the
  // face's normal.
  out.normal = behind && len > 1e-12 * (1.0 + x.norm()) && std::isfinite(len) ? Vec3(d / len) : fn;
  out.depth = std::isfinite(len) ? (behind ? len : -len) : 0.0;
  return true;
}

bool triangle_direction(const World& w, int begin, const Tri& t, const Vec3& x, Vec3& n) {
  const Vec3 p = closest_on_triangle(x, w.x[begin + t[0]], w.x[begin + t[1]], w.x[begin + t[2]]);
  const Vec3 d = p - x;
  const double len = d.norm();
  if (len > 1e-12 * (1.0 + x.norm()) && std::isfinite(len)) {
    n = d / len;
    return true;
  }
  return face_normal(w, begin, t, n);
}

Vec3 vertex_pseudonormal(const World& w, int begin, const std::vector<Tri>& faces, const std::vector<int>& vf_start,
                         const std::vector<int>& vf_faces, int u) {
  const Vec3& xu = w.x[begin + u];
  Vec3 n = Vec3::Zero();
  for (int k = vf_start[u]; k < vf_start[u + 1]; ++k) {
    const Tri& t = faces[vf_faces[k]];
    const int j = t[0] == u ? 0 : t[1] == u ? 1 : 2;
    const Vec3 e1 = w.x[begin + t[(j + 1) % 3]] - xu, e2 = w.x[begin + t[(j + 2) % 3]] - xu;
    const Vec3 c = e1.cross(e2);
    const double len = c.norm();
    if (!(len > 0.0) || !std::isfinite(len)) continue;
    n += (std::atan2(len, e1.dot(e2)) / len) * c;
  }
  return n;
}

std::vector<int> edge_adjacency(const std::vector<Tri>& faces) {
  std::map<std::pair<int, int>, int> directed;
  const int F = static_cast<int>(faces.size());
  for (int f = 0; f < F; ++f)
    for (int k = 0; k < 3; ++k) directed[{faces[f][k], faces[f][(k + 1) % 3]}] = f;
  std::vector<int> adjacent(3 * static_cast<std::size_t>(F), -1);
  for (int f = 0; f < F; ++f)
    for (int k = 0; k < 3; ++k) {
      const auto it = directed.find({faces[f][(k + 1) % 3], faces[f][k]});
      adjacent[3 * f + k] = it == directed.end() ? f : it->second;
    }
  return adjacent;
}

}  // namespace harness
