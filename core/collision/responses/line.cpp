#include "core/collision/responses/line.hpp"

#include "core/collision/responses/directions.hpp"
#include "core/collision/responses/force_rule.hpp"
#include "core/device/contact_kernels.hpp"
#include "core/parallel.hpp"

#include <algorithm>

namespace harness {

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
    // Two loops over the chunk: the nearest host of every contact, then every direction (each
    // loop's iterations short and independent: the processor overlaps their memory latencies).
    for (std::size_t i = b; i < e; ++i) {
      int h = -1;
      const int found = det.nearest_hosts(w, contacts[i], 1, &h);
      out[i].hosts[0] = found >= 1 ? h : -1;
    }
    for (std::size_t i = b; i < e; ++i) {
      const Contact& c = contacts[i];
      const int h = out[i].hosts[0];
      Push p;  // made here, stored once
      p.guest = c.guest;
      if (h >= 0) {
        p.count = 1;
        p.hosts[0] = h;
        p.weight[0] = 1.0;
        Vec3 dir;
        if (det.contact_direction(w, c, dir)) {  // exact detectors: their outward direction
          p.n = dir;
        } else {
          dir = unit_or_zero(w.x[c.guest] - w.x[h]);
          p.n = dir;
          any = any || dir.squaredNorm() == 0.0 || spec.orient == Orient::outward;
        }
      }
      out[i] = p;
    }
    degenerate[part] = any;
  }
  bool have_center = false;
  Vec3 center = Vec3::Zero(), scratch;
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
      else if (p.count == 1 && spec.orient == Orient::outward && !det.contact_direction(w, contacts[i], scratch) &&
               p.n.dot(host_outward_hint(w, spec.host, p.hosts[0], center)) < 0.0)
        p.n = -p.n;  // oriented by the host's outward normal at its node
    }
  }
  if (force_rule_of(spec).depth) {  // the rule needs each contact's normal and depth
    if (!have_center) center = host_center_of(w, spec.host);
#pragma omp parallel for num_threads(T) if(T > 1) schedule(static)
    for (std::size_t i = 0; i < n; ++i) penalty_depth(w, spec.host, det, contacts[i], center, out[i]);
  }
}

HARNESS_ELIMINATOR(line) {
  EliminatorDef e;
  e.name = "line";
  e.doc = "push along the line to the nearest host node";
  e.make = [] { return std::unique_ptr<CollisionEliminator>(std::make_unique<LineEliminator>()); };
  e.device = dev::kElimLine;
  return e;
}

}  // namespace harness
