#include "core/scene/contact_spec.hpp"

namespace harness {

const std::vector<DetectorName>& detector_names() {
  static const std::vector<DetectorName> names = {
      {DetectorKind::voxel, "voxel", false},
      {DetectorKind::voxel_exact, "voxel_exact", false},
      {DetectorKind::hash, "hash", false},
      {DetectorKind::cgal, "cgal", true},
      {DetectorKind::fcl, "fcl", true},
      {DetectorKind::box, "box", false},
      {DetectorKind::distance_field, "distance_field", false},
  };
  return names;
}

const std::vector<std::pair<EliminatorKind, const char*>>& eliminator_names() {
  static const std::vector<std::pair<EliminatorKind, const char*>> names = {
      {EliminatorKind::line, "line"},
      {EliminatorKind::plane, "plane"},
      {EliminatorKind::projection, "projection"},
      {EliminatorKind::volume, "volume"},
      {EliminatorKind::distance_field, "distance_field"},
  };
  return names;
}

const char* to_string(DetectorKind k) {
  for (const DetectorName& d : detector_names())
    if (d.kind == k) return d.name;
  return "?";
}

const char* to_string(EliminatorKind k) {
  for (const auto& [kind, name] : eliminator_names())
    if (kind == k) return name;
  return "?";
}

}  // namespace harness
