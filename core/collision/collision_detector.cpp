#include "core/collision/collision_detector.hpp"

#include "core/collision/voxel_detector.hpp"

#include <map>
#include <stdexcept>

namespace harness {

namespace {
// Function-local static: safe to use from other static initialisers. Registration happens at
// start-up, before any pair is built, so no locking.
std::map<std::string, DetectorFactory>& registry() {
  static std::map<std::string, DetectorFactory> r;
  return r;
}
}  // namespace

void register_detector(const std::string& name, DetectorFactory factory) {
  if (name == "voxel") throw std::invalid_argument("detector \"voxel\" is built in");
  if (name.empty() || !factory) throw std::invalid_argument("register_detector: empty name or factory");
  registry()[name] = std::move(factory);
}

bool detector_known(const std::string& name) {
  return name == "voxel" || registry().count(name) > 0;
}

std::unique_ptr<CollisionDetector> make_detector(const std::string& name) {
  if (name == "voxel") return std::make_unique<VoxelDetector>();
  auto it = registry().find(name);
  if (it == registry().end())
    throw std::invalid_argument("unknown detector \"" + name +
                                "\" (known: voxel, and cgal/fcl when the references are built)");
  return it->second();
}

}  // namespace harness
