#include "core/collision/responses/plane.hpp"

#include "core/collision/responses/directions.hpp"
#include "core/collision/responses/force_rule.hpp"
#include "core/device/contact_kernels.hpp"
#include "core/parallel.hpp"

namespace harness {

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
      const Vec3 centroid = (w.x[h[0]] + w.x[h[1]] + w.x[h[2]]) / 3.0;
      // The paper's and `outward`: the host's outward hints; `guest`: toward the guest node.
      const bool to_guest = spec.orient == Orient::guest;
      const Vec3 hint = to_guest ? Vec3(w.x[c.guest] - centroid)
                                 : Vec3(host_outward_hint(w, spec.host, h[0], center) +
                                        host_outward_hint(w, spec.host, h[1], center) +
                                        host_outward_hint(w, spec.host, h[2], center));
      const Vec3 second = to_guest ? Vec3(w.x[c.guest] - w.x[h[0]]) : Vec3(centroid - center);
      if (plane_normal(w.x[h[0]], w.x[h[1]], w.x[h[2]], hint, second, p.n)) {
        p.count = 3;
        for (int j = 0; j < 3; ++j) p.hosts[j] = h[j], p.weight[j] = 1.0 / 3.0;
        continue;
      }
    }
    // Too few or collinear neighbours: the line rule with the nearest node (oriented as asked).
    p.n = line_direction(w, spec.host, c.guest, h[0], center);
    if (spec.orient == Orient::outward && p.n.dot(host_outward_hint(w, spec.host, h[0], center)) < 0.0) p.n = -p.n;
    p.count = 1;
    p.hosts[0] = h[0];
    p.weight[0] = 1.0;
  }
  if (force_rule_of(spec).depth) {  // the rule needs each contact's normal and depth
#pragma omp parallel for num_threads(T) if(T > 1) schedule(static)
    for (std::size_t i = 0; i < n; ++i) penalty_depth(w, spec.host, det, contacts[i], center, out[i]);
  }
}

HARNESS_ELIMINATOR(plane) {
  EliminatorDef e;
  e.name = "plane";
  e.doc = "along the normal of the plane through the three nearest host nodes, a third of the reaction to each";
  e.make = [] { return std::unique_ptr<CollisionEliminator>(std::make_unique<PlaneEliminator>()); };
  e.device = dev::kElimPlane;
  return e;
}

}  // namespace harness
