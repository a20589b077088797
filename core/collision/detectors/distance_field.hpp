// DistanceFieldDetector ("distance_field"): the voxel contact method of haptics (voxmap-pointshell,
// McNeely et al. 1999; Barbic and James 2008) on the paper's grid: the host's signed distance
// sampled at the corners of power-of-two voxels, the guest's nodes looked up in it.
//
// The field. The grid covers the host's bounding box plus `margin` voxels on each side (the full
// region; voxel size as the voxel detector's: an explicit size rounded down to a power of two, or
// the automatic one, initializer.hpp resolve_voxel_size). At each corner the exact signed distance
// to the host's current surface: the nearest triangle (Ericson's closest point over the triangles
// bucketed in the grid's cells, searched ring by ring: the brute force's answer), its sign from the angle-weighted pseudonormal of the
// nearest feature (Baerentzen and Aanaes 2005), negative inside. The field is sampled again when a
// host surface vertex has moved more than contacts.N.field_resample voxels since the last sampling
// (default 0.02; the field errs by at most that much in between: the signed distance moves by at
// most the surface's largest displacement), so it follows the host as the paper's grid does
// (rebuilds() counts them). A stale field pushes against where the host was: a bounce leaves
// faster than it came at a quarter voxel (tests: 4 % in speed), within 0.2 % at the default.
//
// A guest node is a contact when its trilinear interpolation phi(x) inside the grid is below 0.
// Error bound (tests/core/collision/test_distance_field.cpp): on a flat face the interpolation is
// exact; for a smooth surface of smallest radius of curvature r it errs by at most
// (h^2 / 8) * 2 / (r - sqrt(3) h), plus the displacement since the last sampling, plus how far the
// mesh lies from the smooth surface. A node outside the grid, or further than the grid's margin
// inside a deep host, is as the field says at its cell (nothing is clamped: the field is exact at
// every corner).
//
// Contact point (contact_point, the penalty rule's and the distance_field eliminator's): depth
// -phi(x), the outward direction the normalised gradient of the interpolant (continuous within a
// cell), the reaction on the triangle nearest to x among the nearest triangles of its cell's eight
// corners (barycentric weights of x's closest point on it): every contact's forces sum to zero.
// The depth penalty along the field's gradient is not the gradient of an energy across cells
// (the energy audit books its work).
#pragma once

#include "core/collision/detectors/collision_detector.hpp"

#include <array>
#include <vector>

namespace harness {

class DistanceFieldDetector final : public CollisionDetector {
 public:

  const char* name() const override { return "distance_field"; }
  void initialize(const World& w, const ContactSpec& spec) override;
  void detect(const World& w, std::vector<Contact>& out) override;
  int nearest_hosts(const World& w, const Contact& c, int k, int* out) const override;
  bool contact_direction(const World& w, const Contact& c, Vec3& n) const override;
  bool contact_point(const World& w, const Contact& c, ContactPoint& out) const override;
  double voxel_size() const override { return h_; }
  bool region(Vec3& lo, Vec3& hi) const override;
  int rebuilds() const override { return rebuilds_; }

  // The field at x (m, negative inside) and its gradient, by trilinear interpolation; false
  // outside the grid. Tests and the analytic checks read it.
  bool field(const Vec3& x, double& phi, Vec3* grad = nullptr) const;
  // The exact signed distance from x to the host's surface at the current positions (what the
  // corners sample), and its nearest triangle.
  double signed_distance(const World& w, const Vec3& x, int* face = nullptr) const;
  // Sample the field again on the current positions (detect() does it when the host has moved).
  void sample(const World& w);

 private:
  bool cell_of(const Vec3& x, std::array<int, 3>& c, Vec3& t) const;
  int corner(int i, int j, int k) const { return (k * (n_[1] + 1) + j) * (n_[0] + 1) + i; }
  Vec3 pseudonormal(const World& w, int face, int feature) const;
  void consider(const World& w, const Vec3& x, int f, double& d2, int& face, int& feature, Vec3& q) const;
  double signed_of(const World& w, const Vec3& x, double d2, int face, int feature, const Vec3& q) const;
  double corner_distance(const World& w, int i, int j, int k, int* face);
  int nearest_face(const World& w, const Vec3& x) const;

  int guest_begin_ = 0, guest_end_ = 0;
  int host_begin_ = 0, host_surface_ = 0;
  int margin_ = 1;
  double resample_ = 0.02;  // ContactSpec::field_resample
  std::vector<Tri> faces_;
  std::vector<int> vf_start_, vf_faces_, adjacent_;
  double h_ = 0.0;
  Vec3 origin_ = Vec3::Zero();  // the grid's lowest corner
  std::array<int, 3> n_{{0, 0, 0}};  // voxels per axis
  std::vector<double> phi_;  // per corner
  std::vector<int> face_;    // per corner: its nearest host triangle
  Points sampled_at_;        // host surface positions at the last sampling
  std::vector<int> bucket_start_, bucket_faces_;  // per cell (CSR): the triangles whose box overlaps it
  std::vector<unsigned> stamp_;  // per triangle: the corner query that last looked at it
  unsigned stamp_now_ = 0;
  int rebuilds_ = 0;
};

}  // namespace harness
