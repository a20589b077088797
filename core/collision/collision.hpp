// Collision: the paper's wrapper, one per contact pair, with one interface for the simulation:
// it owns the pair's detector (make_detector(spec.detector)) and eliminator
// (make_eliminator(spec.eliminator)), and each step detects and then eliminates, adding the
// penalty forces into World::f. It runs after every other force of the step, because the
// automatic force magnitude is derived from them (auto_contact_forces, collision_eliminator.hpp).
#pragma once

#include "core/collision/collision_detector.hpp"
#include "core/collision/collision_eliminator.hpp"
#include "core/collision/contact_spec.hpp"
#include "core/world.hpp"

#include <memory>
#include <vector>

namespace harness {

struct PairStepStats {
  int contacts = 0;             // contacts detected this step
  double t_detect_us = 0.0;     // wall time of detection, microseconds (steady_clock)
  double t_eliminate_us = 0.0;  // wall time of elimination, including the auto force
  double force = 0.0;           // largest force magnitude of a contact this step, N
};

class Collision {
 public:
  // The automatic force separates a contact at v_sep = L / (kSeparationSteps dt), L the voxel
  // size: a pair resting in one voxel leaves it in about this many steps (see
  // auto_contact_forces). 200 injected energy through the voxel-thick contact skin once voxels
  // reached 8 mm (cylinder_press diverged); 2000 keeps the ejection speed at a few cm/s.
  static constexpr double kSeparationSteps = 2000.0;

  // Makes and initializes the detector on the current (rest) positions. Throws
  // std::invalid_argument for an unknown detector, bad body indices, a negative margin, a
  // non-finite or negative force, a bad voxel size, or a region above kMaxVoxels.
  Collision(const World& w, ContactSpec spec);

  // Detect, then eliminate. dt (s) is used by the automatic force only.
  PairStepStats step(World& w, double dt);
  // Detection only (tests, benchmarks, measurement); returns the number of contacts.
  int detect(const World& w);

  const std::vector<Contact>& contacts() const { return contacts_; }
  double voxel_size() const { return detector_->voxel_size(); }
  int rebuilds() const { return detector_->rebuilds(); }
  const ContactSpec& spec() const { return spec_; }
  const CollisionDetector& detector() const { return *detector_; }
  const CollisionEliminator& eliminator() const { return *eliminator_; }
  const std::vector<Push>& pushes() const { return pushes_; }

 private:
  ContactSpec spec_;
  std::unique_ptr<CollisionDetector> detector_;
  std::unique_ptr<CollisionEliminator> eliminator_;
  std::vector<Contact> contacts_;  // reserved for every guest node: no growth per step
  std::vector<Push> pushes_;       // direction and reactions per contact (same capacity)
  std::vector<double> magnitude_;  // force per contact, N (same capacity)
  double length_scale_ = 0.0;      // m, for the automatic force without a grid
  std::vector<int> share_;         // per node: contacts leaning on it (scratch, all zero)
};

}  // namespace harness
