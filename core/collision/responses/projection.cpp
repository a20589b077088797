#include "core/collision/responses/projection.hpp"

#include "core/collision/responses/directions.hpp"
#include "core/collision/responses/plane.hpp"

#include <algorithm>
#include <cmath>

namespace harness {

void ProjectionEliminator::pushes(const World& w, const ContactSpec& spec, const CollisionDetector& det,
                                  const std::vector<Contact>& contacts, std::vector<Push>& out) const {
  PlaneEliminator().pushes(w, spec, det, contacts, out);
  if (contacts.empty()) return;
  const Vec3 center = host_center_of(w, spec.host);
  for (std::size_t i = 0; i < contacts.size(); ++i) penalty_depth(w, spec.host, det, contacts[i], center, out[i]);
}

double project_pushes(World& w, const std::vector<Push>& pushes, double h) {
  auto inv = [&w](int i) { return w.is_free(i) ? w.inv_m[i] : 0.0; };
  double largest = 0.0;
  for (const Push& p : pushes) {
    if (p.count == 0 || !(p.depth > 0.0) || p.normal.squaredNorm() == 0.0) continue;
    double denom = inv(p.guest);
    for (int k = 0; k < p.count; ++k) denom += p.weight[k] * p.weight[k] * inv(p.hosts[k]);
    if (!(denom > 0.0)) continue;
    const double lambda = p.depth / denom;
    auto move = [&](int node, const Vec3& dx) {
      w.x[node] += dx;
      w.v[node] += dx / h;
      w.f[node] += (w.m[node] / (h * h)) * dx;
    };
    const Vec3 dg = (inv(p.guest) * lambda) * p.normal;
    move(p.guest, dg);
    largest = std::max(largest, dg.norm());
    for (int k = 0; k < p.count; ++k) move(p.hosts[k], (-p.weight[k] * inv(p.hosts[k]) * lambda) * p.normal);
  }
  return largest;
}

HARNESS_ELIMINATOR(projection) {
  EliminatorDef e;
  e.name = "projection";
  e.doc = "move the node to the surface after the position update";
  e.make = [] { return std::unique_ptr<CollisionEliminator>(std::make_unique<ProjectionEliminator>()); };
  e.projects = true;
  return e;
}

}  // namespace harness
