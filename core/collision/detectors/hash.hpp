// HashDetector ("hash"): spatial hashing after Teschner, Heidelberger, Mueller, Pomeranets and
// Gross, "Optimized Spatial Hashing for Collision Detection of Deformable Objects" (VMV 2003),
// adapted from tetrahedra to a closed surface. Every step:
//   1. each host surface triangle is entered in the hash cells its bounding box covers: cells of
//      edge c (default: the host surface's mean edge length at rest), the cell (i, j, k) in bucket
//      (i p1 xor j p2 xor k p3) mod n with p1 = 73856093, p2 = 19349663, p3 = 83492791 and n a
//      prime of about four entries per triangle; buckets carry a time stamp instead of being
//      cleared (an entry counts only when its bucket's stamp is this step's);
//   2. each guest vertex inside the host's bounding box is tested exactly: the signed crossings of
//      the ray from it along the shortest way out of the box (one of +-x, +-y, +-z: the fewest
//      cells) with the triangles hashed along the cells it passes (parity of
//      an outward-oriented closed surface: inside when they sum to one; ties, a ray through an
//      edge or a vertex, are broken by simulating an infinitesimal shift of the ray); its depth and
//      contact point come from the nearest triangle, searched in growing shells of cells.
// Boundary convention: a vertex on the host surface counts as outside, as CGAL's strict test has
// it (within floating-point resolution). Contacts are reported in guest node order with key = the
// nearest host triangle; nearest_hosts(), contact_direction() and contact_point() answer from it,
// as the exact detectors do.
#pragma once

#include "core/collision/detectors/collision_detector.hpp"

#include <cstdint>
#include <vector>

namespace harness {

class HashDetector final : public CollisionDetector {
 public:
  const char* name() const override { return "hash"; }
  void initialize(const World& w, const ContactSpec& spec) override;
  void detect(const World& w, std::vector<Contact>& out) override;
  int nearest_hosts(const World& w, const Contact& c, int k, int* out) const override;
  bool contact_direction(const World& w, const Contact& c, Vec3& n) const override;
  bool contact_point(const World& w, const Contact& c, ContactPoint& out) const override;
  double cell_size() const { return cell_; }
  std::size_t table_size() const { return head_.size(); }

  // Whether x is strictly inside the host surface as hashed by the last detect() (tests).
  bool inside(const World& w, const Vec3& x);
  // The host triangle nearest to x (-1 without triangles), as hashed by the last detect().
  int nearest_triangle(const World& w, const Vec3& x);

 private:
  struct Cell {
    long long i, j, k;
  };
  Cell cell_of(const Vec3& x) const;
  std::size_t bucket(long long i, long long j, long long k) const;
  void hash_host(const World& w);
  int crossings(const World& w, const Vec3& p, const Tri& t, int axis, bool up) const;

  int guest_ = -1;  // the guest body
  int host_begin_ = 0;
  std::vector<Tri> faces_;
  double cell_ = 0.0;
  std::vector<std::uint32_t> stamp_;  // per bucket: the step its list belongs to
  std::vector<int> head_;             // per bucket: first entry, -1 none
  std::vector<int> entry_tri_, entry_next_;
  std::uint32_t now_ = 0;
  std::vector<std::uint32_t> seen_;   // per triangle: the query that last looked at it
  std::uint32_t query_ = 0;
  Vec3 lo_ = Vec3::Zero(), hi_ = Vec3::Zero();  // host bounding box this step
};

}  // namespace harness
