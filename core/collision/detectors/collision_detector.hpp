// CollisionDetector: the paper's interface for collision detection, and the one factory that
// makes a detector by name (the registry below). The voxel detector (the
// paper's, voxel.hpp) lives here in core; the exact detectors (CGAL, FCL) live in reference/,
// and a program that links the reference library passes its maker (ExactDetectorMaker).
#pragma once

#include "core/scene/contact_spec.hpp"
#include "core/world.hpp"

#include <memory>
#include <string>
#include <vector>

namespace harness {

// One detected contact: a guest node (global index) that detection reports as colliding.
// `key` is detector-specific (the voxel detector stores the linear voxel index).
struct Contact {
  int guest = -1;
  int key = -1;
};

// Where an exact detector sees a contact: the host surface point nearest to the guest node, as
// barycentric weights on the vertices of its triangle, the outward normal there and the depth
// of the node (m, >= 0 inside).
struct ContactPoint {
  Vec3 normal = Vec3::Zero();
  double depth = 0.0;
  int hosts[3] = {-1, -1, -1};
  double weight[3] = {0.0, 0.0, 0.0};
};

class CollisionDetector {
 public:
  virtual ~CollisionDetector() = default;
  virtual const char* name() const = 0;
  // Configures the detector for one pair, once, when the simulation is built (rest state): it
  // keeps what it needs of the spec (bodies, grid, cell) and builds its structures; the pair has
  // been checked (check_pair, collision.hpp). Then detect() runs each step without the spec.
  virtual void initialize(const World& w, const ContactSpec& spec) = 0;
  // Detect on the current positions; `out` is cleared first and reused without reallocation.
  virtual void detect(const World& w, std::vector<Contact>& out) = 0;
  // Up to k host nodes (global indices) nearest to the guest node of contact c, searched in the
  // detector's neighbourhood of the contact, nearest first. Returns how many were written.
  // nearest_hosts() and contact_direction() are called from several threads at once (the
  // eliminators' parallel loops): they must not modify the detector.
  virtual int nearest_hosts(const World& w, const Contact& c, int k, int* out) const = 0;
  // Exact detectors know the direction that pushes a contact's guest node out of the host
  // (unit vector, written to n; never true with a zero n); the eliminators then use it instead
  // of their geometric rule for the guest's direction. The voxel detector knows none (false).
  virtual bool contact_direction(const World& w, const Contact& c, Vec3& n) const {
    (void)w, (void)c, (void)n;
    return false;
  }
  // The contact's nearest host surface point (exact detectors); false when the detector does
  // not know it (the voxel detector). Called from several threads at once, like the above.
  virtual bool contact_point(const World& w, const Contact& c, ContactPoint& out) const {
    (void)w, (void)c, (void)out;
    return false;
  }
  // Voxel size in use, m (0 for detectors without a grid).
  virtual double voxel_size() const { return 0.0; }
  // The box the detector's grid covers this step (world coordinates, m); false without a grid.
  virtual bool region(Vec3& lo, Vec3& hi) const {
    (void)lo, (void)hi;
    return false;
  }
  // Times the detection region was rebuilt because the host outgrew it.
  virtual int rebuilds() const { return 0; }
  // Guest nodes the last detect() found inside beyond the band in which its answer is guaranteed
  // (voxel_exact.hpp); -1 for detectors without such a band (every other detector).
  virtual int beyond_band() const { return -1; }
};

// Makes the exact detectors by name (reference/: reference::make_exact_detector); null in a
// program without the reference library.
using ExactDetectorMaker = std::unique_ptr<CollisionDetector> (*)(const std::string& name);

// The detectors' registry. A detector is its file pair in core/collision/detectors/; its source
// defines it with a line `HARNESS_DETECTOR(stem)`, which CMake finds there and calls through a
// generated list (build/generated/detector_list.hpp), so adding one touches no other hand-written
// file. The key table (contacts.N.detector), the schema and the device's refusals read it.
struct DetectorDef {
  const char* name = "";
  const char* doc = "";  // what it does, for the key's description and docs/scenes.md
  // Made by the reference library (FCL, CGAL: ExactDetectorMaker); `make` is then null.
  bool exact = false;
  std::unique_ptr<CollisionDetector> (*make)() = nullptr;
  // Its device kernel (core/device/contact_kernels.hpp: kDet*), or -1: `--device` refuses it.
  int device = -1;
};
const std::vector<DetectorDef>& detectors();
const DetectorDef* find_detector(const std::string& name);
// The detectors as docs/scenes.md lists them ("Detectors"; `harness rules` prints it).
std::string detectors_markdown();

// The detector of that name. An exact one without a maker throws std::invalid_argument saying
// that this program has no reference library.
std::unique_ptr<CollisionDetector> make_detector(const std::string& name, ExactDetectorMaker exact);

#define HARNESS_DETECTOR(stem) DetectorDef make_detector_##stem()

}  // namespace harness
