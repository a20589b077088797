#include "core/collision/responses/collision_eliminator.hpp"

#include "core/collision/responses/field.hpp"
#include "core/collision/responses/force_rules.hpp"
#include "core/collision/responses/line.hpp"
#include "core/collision/responses/plane.hpp"
#include "core/collision/responses/projection.hpp"
#include "core/collision/responses/volume.hpp"

#include <stdexcept>

namespace harness {

std::unique_ptr<CollisionEliminator> make_eliminator(EliminatorKind kind) {
  switch (kind) {
    case EliminatorKind::line: return std::make_unique<LineEliminator>();
    case EliminatorKind::plane: return std::make_unique<PlaneEliminator>();
    case EliminatorKind::projection: return std::make_unique<ProjectionEliminator>();
    case EliminatorKind::volume: return std::make_unique<VolumeEliminator>();
    case EliminatorKind::distance_field: return std::make_unique<FieldEliminator>();
  }
  throw std::invalid_argument("unknown eliminator kind");
}

void CollisionEliminator::eliminate(World& w, const ContactSpec& spec, const CollisionDetector& det,
                                    const std::vector<Contact>& contacts, double force) const {
  std::vector<Push> p;
  pushes(w, spec, det, contacts, p);
  apply_pushes(w, p, std::vector<double>(p.size(), force));
}

}  // namespace harness
