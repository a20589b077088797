// BoxDetector ("box"): the baseline a broad phase has to beat. Every step the host's current
// axis-aligned bounding box is computed and every guest node inside it (boundary included) is a
// contact, in guest node order (key -1). It knows nothing of the host's surface: no direction, no
// contact point, no depth; its precision is the share of the box's guest nodes that truly
// penetrate. nearest_hosts() answers by brute force over the host's surface vertices (the k
// nearest, nearest first), so that its contacts feed the eliminators like any detector's; that
// search costs O(contacts x host surface) and belongs to the elimination, not to the detection.
#pragma once

#include "core/collision/detectors/collision_detector.hpp"

namespace harness {

class BoxDetector final : public CollisionDetector {
 public:
  const char* name() const override { return "box"; }
  void initialize(const World& w, const ContactSpec& spec) override;
  void detect(const World& w, std::vector<Contact>& out) override;
  int nearest_hosts(const World& w, const Contact& c, int k, int* out) const override;
  bool region(Vec3& lo, Vec3& hi) const override;

 private:
  int guest_begin_ = 0, guest_end_ = 0;
  int host_begin_ = 0, host_surface_ = 0;
  Vec3 lo_ = Vec3::Zero(), hi_ = Vec3::Zero();  // the host's box this step
  bool stepped_ = false;
};

}  // namespace harness
