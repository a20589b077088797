#include "core/collision/responses/field.hpp"

#include "core/parallel.hpp"

namespace harness {

void FieldEliminator::pushes(const World& w, const ContactSpec& spec, const CollisionDetector& det,
                             const std::vector<Contact>& contacts, std::vector<Push>& out) const {
  (void)spec;
  out.resize(contacts.size());
  const std::size_t n = contacts.size();
  const int T = threads_for(n, 2048);
  // Contacts are independent: each push is written in its own slot, whatever the thread.
#pragma omp parallel for num_threads(T) if(T > 1) schedule(dynamic, 256)
  for (std::size_t i = 0; i < n; ++i) {
    Push& p = out[i];
    p = Push{};
    p.guest = contacts[i].guest;
    ContactPoint cp;
    if (!det.contact_point(w, contacts[i], cp)) continue;  // no push: count 0
    p.n = p.normal = cp.normal;
    p.depth = cp.depth;
    p.count = 3;
    for (int k = 0; k < 3; ++k) p.hosts[k] = cp.hosts[k], p.weight[k] = cp.weight[k];
  }
}

HARNESS_ELIMINATOR(field) {
  EliminatorDef e;
  e.name = "distance_field";
  e.doc = "with detector distance_field: along the field's gradient, as deep as the field says, the reaction on the nearest host triangle";
  e.make = [] { return std::unique_ptr<CollisionEliminator>(std::make_unique<FieldEliminator>()); };
  e.detector = "distance_field";
  return e;
}

}  // namespace harness
