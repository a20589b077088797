#include "core/collision/detectors/collision_detector.hpp"

#include "core/collision/detectors/box.hpp"
#include "core/collision/detectors/distance_field.hpp"
#include "core/collision/detectors/hash.hpp"
#include "core/collision/detectors/voxel.hpp"
#include "core/collision/detectors/voxel_exact.hpp"

#include <stdexcept>

namespace harness {

std::unique_ptr<CollisionDetector> make_detector(DetectorKind kind, ExactDetectorMaker exact) {
  switch (kind) {
    case DetectorKind::voxel: return std::make_unique<VoxelDetector>();
    case DetectorKind::hash: return std::make_unique<HashDetector>();
    case DetectorKind::voxel_exact: return std::make_unique<VoxelExactDetector>();
    case DetectorKind::box: return std::make_unique<BoxDetector>();
    case DetectorKind::distance_field: return std::make_unique<DistanceFieldDetector>();
    case DetectorKind::cgal:
    case DetectorKind::fcl: break;
  }
  if (!exact)
    throw std::invalid_argument(std::string("detector \"") + to_string(kind) +
                                "\" needs the reference library (FCL, CGAL), which this program was built without "
                                "(cmake -DHARNESS_BUILD_REFERENCE=ON)");
  return exact(kind);
}

}  // namespace harness
