// Exact detection driving elimination, behind the core CollisionDetector interface:
//  "cgal": contacts are the guest nodes (all of them, interior ones too) strictly inside the
//          host's closed surface (Side_of_triangle_mesh); a contact's key is the host triangle
//          holding the surface point nearest to the node.
//  "fcl":  contacts are the guest surface vertices of guest triangles that intersect a host
//          triangle (FCL BVH traversal); the key is, of the host triangles intersecting the
//          node's triangles, the one nearest to the node.
// nearest_hosts() returns the vertices (global indices) of the key triangle, nearest first, at
// most 3 whatever k asks. contact_direction() (what the eliminators push the guest along):
//  "cgal": from the node to the nearest point of the host surface (outward, since the node is
//          inside), or the key triangle's outward normal when the node lies on it;
//  "fcl":  the key triangle's outward normal (FCL's contact normal of the pair).
#pragma once

#include "core/collision/detectors/collision_detector.hpp"
#include "reference/cgal_surface.hpp"
#include "reference/fcl_surface.hpp"

namespace harness {

class CgalDetector final : public CollisionDetector {
 public:
  const char* name() const override { return "cgal"; }
  void initialize(const World& w, const ContactSpec& spec) override;
  void detect(const World& w, std::vector<Contact>& out) override;
  int nearest_hosts(const World& w, const Contact& c, int k, int* out) const override;
  bool contact_direction(const World& w, const Contact& c, Vec3& n) const override;
  bool contact_point(const World& w, const Contact& c, ContactPoint& out) const override;

 private:
  CgalSurface host_surface_;
  int host_ = -1, guest_ = -1;  // the bodies
  int host_begin_ = 0, guest_begin_ = 0;
  std::vector<int> last_face_;  // per guest node: its closest host face when last inside (a seed), or -1
};

class FclDetector final : public CollisionDetector {
 public:
  explicit FclDetector(FclBv bv = FclBv::aabb) : host_(bv), guest_(bv) {}
  const char* name() const override { return "fcl"; }
  void initialize(const World& w, const ContactSpec& spec) override;
  void detect(const World& w, std::vector<Contact>& out) override;
  int nearest_hosts(const World& w, const Contact& c, int k, int* out) const override;
  bool contact_direction(const World& w, const Contact& c, Vec3& n) const override;
  bool contact_point(const World& w, const Contact& c, ContactPoint& out) const override;

 private:
  FclSurface host_, guest_;
  int host_body_ = -1, guest_body_ = -1;
  int host_begin_ = 0;
  std::vector<TrianglePair> pairs_;
  std::vector<double> best_d2_;  // per guest surface vertex: distance^2 to its nearest host triangle
  std::vector<int> best_tri_;    // that triangle, -1 when none intersects
  std::vector<int> touched_;     // guest surface vertices with best_tri_ set this call
};

// The exact detectors' maker (an ExactDetectorMaker: SimulationOptions, RunOptions): "cgal" and
// "fcl"; throws std::invalid_argument for any other kind.
std::unique_ptr<CollisionDetector> make_exact_detector(const std::string& name);

}  // namespace harness
