#include "core/collision/eliminators.hpp"

#include "core/parallel.hpp"

#include <algorithm>
#include <cmath>

namespace harness {

namespace {

bool finite(const Vec3& a) { return std::isfinite(a.x()) && std::isfinite(a.y()) && std::isfinite(a.z()); }

// a / |a| when that is a finite unit vector, else zero.
Vec3 unit_or_zero(const Vec3& a) {
  const double n = a.norm();
  if (!(n > 0.0) || !std::isfinite(n)) {
    // |a| may overflow for huge finite components: rescale before giving up.
    const double s = a.cwiseAbs().maxCoeff();
    if (!(s > 0.0) || !std::isfinite(s)) return Vec3::Zero();
    const Vec3 b = a / s;
    return b / b.norm();
  }
  const Vec3 u = a / n;
  return finite(u) ? u : Vec3::Zero();
}

Vec3 host_center_of(const World& w, int host) {
  Vec3 lo, hi;
  body_bounds(w, host, lo, hi);
  return 0.5 * (lo + hi);
}

}  // namespace

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

void LineEliminator::pushes(const World& w, const ContactSpec& spec, const CollisionDetector& det,
                            const std::vector<Contact>& contacts, std::vector<Push>& out) const {
  out.resize(contacts.size());
  // Contacts are independent: parallel chunks, each push written in its own slot. A contact whose
  // guest and host nodes coincide needs the host centre: its chunk is flagged and the contact is
  // finished afterwards, on one thread (the centre computed once, and only then).
  const std::size_t n = contacts.size();
  const int T = threads_for(n, 4096);
  const int C = T == 1 ? 1 : std::min(64, 4 * T);
  bool degenerate[64] = {};
#pragma omp parallel for num_threads(T) if(T > 1) schedule(dynamic, 1)
  for (int part = 0; part < C; ++part) {
    std::size_t b, e;
    split_range(n, C, part, b, e);
    bool any = false;  // local: the flags share a cache line
    for (std::size_t i = b; i < e; ++i) {
      const Contact& c = contacts[i];
      Push& p = out[i];
      p = Push{};
      p.guest = c.guest;
      int h = -1;
      if (det.nearest_hosts(w, c, 1, &h) < 1) continue;
      p.count = 1;
      p.hosts[0] = h;
      p.weight[0] = 1.0;
      if (det.contact_direction(w, c, p.n)) continue;  // exact detectors: their outward direction
      p.n = unit_or_zero(w.x[c.guest] - w.x[h]);
      any = any || p.n.squaredNorm() == 0.0;
    }
    degenerate[part] = any;
  }
  bool have_center = false;
  Vec3 center = Vec3::Zero();
  for (int part = 0; part < C; ++part) {
    if (!degenerate[part]) continue;
    if (!have_center) {
      center = host_center_of(w, spec.host);
      have_center = true;
    }
    std::size_t b, e;
    split_range(n, C, part, b, e);
    for (std::size_t i = b; i < e; ++i) {
      Push& p = out[i];
      if (p.count == 1 && p.n.squaredNorm() == 0.0)
        p.n = line_direction(w, spec.host, contacts[i].guest, p.hosts[0], center);
    }
  }
}

void PlaneEliminator::pushes(const World& w, const ContactSpec& spec, const CollisionDetector& det,
                             const std::vector<Contact>& contacts, std::vector<Push>& out) const {
  out.resize(contacts.size());
  if (contacts.empty()) return;
  const Vec3 center = host_center_of(w, spec.host);
  const std::size_t n = contacts.size();
  const int T = threads_for(n, 2048);
  // Contacts are independent: each push is written in its own slot, whatever the thread.
#pragma omp parallel for num_threads(T) if(T > 1) schedule(dynamic, 256)
  for (std::size_t i = 0; i < n; ++i) {
    const Contact& c = contacts[i];
    Push& p = out[i];
    p = Push{};
    p.guest = c.guest;
    int h[3] = {-1, -1, -1};
    const int k = det.nearest_hosts(w, c, 3, h);
    if (k < 1) continue;
    if (k == 3) {
      const Vec3 hint = host_outward_hint(w, spec.host, h[0], center) +
                        host_outward_hint(w, spec.host, h[1], center) +
                        host_outward_hint(w, spec.host, h[2], center);
      const Vec3 centroid = (w.x[h[0]] + w.x[h[1]] + w.x[h[2]]) / 3.0;
      if (plane_normal(w.x[h[0]], w.x[h[1]], w.x[h[2]], hint, centroid - center, p.n)) {
        p.count = 3;
        for (int j = 0; j < 3; ++j) p.hosts[j] = h[j], p.weight[j] = 1.0 / 3.0;
        continue;
      }
    }
    // Too few or collinear neighbours: the line rule with the nearest node.
    p.n = line_direction(w, spec.host, c.guest, h[0], center);
    p.count = 1;
    p.hosts[0] = h[0];
    p.weight[0] = 1.0;
  }
}

}  // namespace harness
