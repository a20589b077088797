// FCL on deforming closed triangle surfaces, and libccd (through FCL's GJK/EPA) on convex hulls.
// No FCL type appears here: the models sit behind a pointer, compiled in reference/fcl_surface.cpp.
#pragma once

#include "core/types.hpp"

#include <memory>
#include <string>
#include <vector>

namespace harness {

// Bounding volume of the FCL hierarchy. AABB is the default: on deforming meshes it refits
// faster and traverses no slower than OBBRSS (numbers in reference/README.md).
enum class FclBv { aabb, obbrss };

// When a refitted hierarchy is thrown away and rebuilt. Refitting keeps the tree's topology, so
// volumes of nodes whose triangles drifted apart grow and overlap. The cost below is the summed
// surface area of all node volumes over that of the vertices' bounding box (a surface-area-
// heuristic estimate of traversal cost), compared with its value right after the last full build.
// FCL's bottom-up OBBRSS refit merges child OBBs loosely: it multiplies that cost by about ten
// even when nothing moved, so with OBBRSS this policy rebuilds every other update.
struct FclRefitPolicy {
  int rebuild_every = 100;    // refits before a full rebuild regardless of the cost
  double cost_growth = 1.5;   // rebuild once cost > cost_growth * cost after the last rebuild
};

class FclSurface {
 public:
  explicit FclSurface(FclBv bv = FclBv::aabb, FclRefitPolicy policy = {});
  ~FclSurface();
  FclSurface(FclSurface&&) noexcept;
  FclSurface& operator=(FclSurface&&) noexcept;

  // F: #F triangles over vertices 0..n_vertices-1 (kept; positions come with update()).
  void set_topology(int n_vertices, const std::vector<Tri>& F);
  // Replaces the positions with points[0..n_vertices): the first call builds the hierarchy,
  // later calls refit it bottom-up, or rebuild it when the policy says so.
  void update(const Vec3* points);

  FclBv bv() const;
  int num_vertices() const;
  const std::vector<Tri>& faces() const;
  const Vec3& vertex(int i) const;  // current position
  bool ready() const;
  int builds() const;  // full builds (the first one included)
  int refits() const;
  double tree_cost() const;  // summed node surface area / vertex bounding box area, now

  struct Impl;
  Impl& impl() { return *impl_; }
  const Impl& impl() const { return *impl_; }

 private:
  std::unique_ptr<Impl> impl_;
};

// One pair of intersecting triangles: a's triangle, b's triangle, and the local penetration depth
// that FCL reports for the pair with enable_contact (the depth of the deepest vertex of one
// triangle below the other's plane; `has_depth` is false where FCL would add no contact).
struct TrianglePair {
  int a = -1, b = -1;
  double depth = 0.0;
  bool has_depth = false;
};

// Every intersecting triangle pair of two updated surfaces of the same bounding volume type,
// by FCL's BVH traversal with num_max_contacts unbounded (one contact per pair). The traversal
// node is driven directly rather than through fcl::collide, which deep-copies both AABB models
// on every call; with_depth adds FCL's enable_contact depth of each pair found.
void intersecting_pairs(FclSurface& a, FclSurface& b, std::vector<TrianglePair>& out,
                        bool with_depth);

// The oracle: every triangle of a against every triangle of b with FCL's triangle test.
void intersecting_pairs_brute_force(const FclSurface& a, const FclSurface& b,
                                    std::vector<TrianglePair>& out);

// fcl::collide itself, for validation and benchmarks: contacts returned, distinct triangle pairs
// among them, deepest contact. Use it with OBBRSS: for AABB models fcl::collide deep-copies both
// models on every call, and FCL 0.7's BVHModel copy constructor mallocs what its destructor frees
// with delete[] (AddressSanitizer: alloc-dealloc-mismatch), so it throws std::invalid_argument.

struct FclCollideResult {
  int contacts = 0;
  int pairs = 0;
  double max_depth = 0.0;
};
FclCollideResult fcl_collide(const FclSurface& a, const FclSurface& b, bool enable_contact);

// Signed distance between two convex polytopes (vertices V, outward triangles F) by FCL's
// GJK/EPA with the libccd solver (GST_LIBCCD): positive = separation, negative = penetration
// depth. Returns false when the solver fails on the configuration.
bool convex_signed_distance(const Points& Va, const std::vector<Tri>& Fa, const Points& Vb,
                            const std::vector<Tri>& Fb, double& distance);

// "0.7.0"
std::string fcl_version();

}  // namespace harness
