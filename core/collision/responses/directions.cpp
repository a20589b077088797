#include "core/collision/responses/directions.hpp"

#include "core/geometry.hpp"

#include <algorithm>
#include <cmath>

namespace harness {

// unit_or_zero where |a| is zero, NaN or infinite: |a| may overflow for huge finite components,
// so rescale before giving up.
Vec3 unit_or_zero_rescaled(const Vec3& a) {
  const double s = a.cwiseAbs().maxCoeff();
  if (!(s > 0.0) || !std::isfinite(s)) return Vec3::Zero();
  const Vec3 b = a / s;
  return b / b.norm();
}

Vec3 host_center_of(const World& w, int host) {
  Vec3 lo, hi;
  body_bounds(w, host, lo, hi);
  return 0.5 * (lo + hi);
}

Vec3 host_outward_hint(const World& w, int host, int node, const Vec3& host_center) {
  const Body& b = w.bodies[host];
  const int s = node - b.begin;
  if (s < b.n_surface && static_cast<int>(b.vf_start.size()) > s + 1) {
    const Vec3 n = unit_or_zero(vertex_normal(w, host, s));
    if (n.squaredNorm() > 0.0) return n;
  }
  return unit_or_zero(w.x[node] - host_center);
}

Vec3 line_direction(const World& w, int host, int guest_node, int host_node,
                    const Vec3& host_center) {
  Vec3 n = unit_or_zero(w.x[guest_node] - w.x[host_node]);
  if (n.squaredNorm() > 0.0) return n;
  n = host_outward_hint(w, host, host_node, host_center);
  if (n.squaredNorm() > 0.0) return n;
  n = unit_or_zero(w.x[guest_node] - host_center);
  if (n.squaredNorm() > 0.0) return n;
  return Vec3::UnitZ();
}

bool plane_normal(const Vec3& p0, const Vec3& p1, const Vec3& p2, const Vec3& hint,
                  const Vec3& second_hint, Vec3& n) {
  const Vec3 e1 = p1 - p0, e2 = p2 - p0;
  const double s2 = std::max({e1.squaredNorm(), e2.squaredNorm(), (p2 - p1).squaredNorm()});
  const Vec3 c = e1.cross(e2);
  // Negated comparison: also rejects NaN and the all-coincident case (0 < 0 is false).
  if (!(c.norm() >= 1e-12 * s2) || !(s2 > 0.0)) return false;
  Vec3 u = unit_or_zero(c);
  if (u.squaredNorm() == 0.0) return false;
  double side = u.dot(hint);
  if (side == 0.0 || !std::isfinite(side)) side = u.dot(second_hint);
  if (side < 0.0) u = -u;
  n = u;
  return true;
}

void penalty_depth(const World& w, int host, const CollisionDetector& det, const Contact& c, const Vec3& host_center,
                   Push& p) {
  if (p.count == 0) return;
  ContactPoint cp;
  if (det.contact_point(w, c, cp)) {  // exact: the closest point, its triangle takes the reaction
    p.normal = cp.normal;
    p.depth = cp.depth;
    p.count = 3;
    for (int k = 0; k < 3; ++k) p.hosts[k] = cp.hosts[k], p.weight[k] = cp.weight[k];
    return;
  }
  if (p.count == 3) {  // the plane: the closest point of the triangle of the three host nodes
    const Vec3 &a = w.x[p.hosts[0]], &b = w.x[p.hosts[1]], &q = w.x[p.hosts[2]];
    p.normal = p.n;
    p.depth = (a - w.x[p.guest]).dot(p.normal);
    barycentric(closest_on_triangle(w.x[p.guest], a, b, q), a, b, q, p.weight);
    return;
  }
  p.normal = host_outward_hint(w, host, p.hosts[0], host_center);
  p.depth = (w.x[p.hosts[0]] - w.x[p.guest]).dot(p.normal);
}

}  // namespace harness
