#include "core/collision/responses/volume.hpp"

#include "core/collision/intersection_volume.hpp"

#include <algorithm>
#include <cmath>

namespace harness {

void VolumeEliminator::pushes(const World& w, const ContactSpec& spec, const CollisionDetector& det,
                              const std::vector<Contact>& contacts, std::vector<Push>& out) const {
  (void)w, (void)spec, (void)det, (void)contacts;
  out.clear();
}

double volume_pixel(const World& w, int host, int guest, double requested) {
  if (requested > 0.0) return requested;
  return 0.5 * std::min(rest_surface_edge(w, host), rest_surface_edge(w, guest));
}

double restrict_volume(World& w, int host, int guest, double pixel, double h, VolumeStep& out, bool invert) {
  out.moves.clear();
  out.pixel = pixel;
  const IntersectionVolume iv = intersection_volume(w, w.x, host, guest, pixel);
  out.volume = iv.volume;
  if (!(iv.volume > 0.0)) return 0.0;
  auto inv = [&w](int i) { return w.is_free(i) ? w.inv_m[i] : 0.0; };
  double denom = 0.0;
  for (int body : {host, guest}) {
    const Body& b = w.bodies[body];
    const std::vector<Vec3>& g = body == host ? iv.grad_a : iv.grad_b;
    for (int s = 0; s < b.n_surface; ++s) denom += inv(b.surface_node(s)) * g[s].squaredNorm();
  }
  if (!(denom > 0.0)) return 0.0;
  const double lambda = (invert ? -1.0 : 1.0) * iv.volume / denom;
  double largest = 0.0;
  for (int body : {host, guest}) {
    const Body& b = w.bodies[body];
    const std::vector<Vec3>& g = body == host ? iv.grad_a : iv.grad_b;
    for (int s = 0; s < b.n_surface; ++s) {
      const int i = b.surface_node(s);
      if (g[s].squaredNorm() == 0.0 || inv(i) == 0.0) continue;
      const Vec3 dx = (-lambda * inv(i)) * g[s];
      w.x[i] += dx;
      w.v[i] += dx / h;
      w.f[i] += (w.m[i] / (h * h)) * dx;
      out.moves.emplace_back(i, dx);
      largest = std::max(largest, dx.norm());
    }
  }
  return largest;
}

HARNESS_ELIMINATOR(volume) {
  EliminatorDef e;
  e.name = "volume";
  e.doc = "a restriction with a practical bound: after the position update, both bodies' surface vertices moved along the gradient of the volume they share, by layered depth images, one Newton step toward none";
  e.make = [] { return std::unique_ptr<CollisionEliminator>(std::make_unique<VolumeEliminator>()); };
  e.projects = true;
  return e;
}

}  // namespace harness
