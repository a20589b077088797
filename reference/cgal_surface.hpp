// Exact ground truth on a closed triangle surface with CGAL (Exact_predicates_inexact_constructions
// kernel: predicates exact, constructions such as distances in double). No CGAL type appears here:
// the CGAL state sits behind a pointer and is compiled in reference/cgal_surface.cpp only.
#pragma once

#include "core/types.hpp"

#include <memory>
#include <string>
#include <vector>

namespace harness {

// Where a point lies with respect to a closed surface (CGAL's Bounded_side).
enum class SurfaceSide { outside = -1, boundary = 0, inside = 1 };

// Where a segment crosses a surface: its parameter along the segment (0 at the start, 1 at the
// end) and the crossed face's unit outward normal (zero for a collapsed face).
struct SurfaceCrossing {
  double t = 0.0;
  Vec3 normal = Vec3::Zero();
};

// A closed, outward-oriented triangle surface whose vertices move: the topology is set once,
// the points are replaced every measured step and the AABB tree (and everything cached from
// it) is rebuilt on each update, because CGAL 5.5 cannot refit and a stale tree answers
// silently wrong.
class CgalSurface {
 public:
  CgalSurface();
  ~CgalSurface();
  CgalSurface(CgalSurface&&) noexcept;
  CgalSurface& operator=(CgalSurface&&) noexcept;

  // F: #F triangles over vertices 0..n_vertices-1, counter-clockwise seen from outside. Throws
  // std::invalid_argument if they do not form a closed 2-manifold triangle mesh.
  void set_topology(int n_vertices, const std::vector<Tri>& F);
  // Replaces the vertex positions with points[0..n_vertices). CGAL 5.5's AABB tree has no refit:
  // its boxes are the faces' boxes grown by a margin (a quarter of the mean edge), and the tree is
  // rebuilt only when some vertex has moved farther than that since its last build; in between
  // every face lies inside its box and every query stays exact.
  void update(const Vec3* points);
  long long tree_rebuilds() const;  // update() calls that rebuilt the tree since set_topology()

  int num_vertices() const;
  const std::vector<Tri>& faces() const;
  bool ready() const;  // update() has been called since set_topology()

  // Queries are const but not safe to run concurrently on one surface: the first distance query
  // after an update builds the tree's kd-tree of seeds.
  // Exact classification (Side_of_triangle_mesh).
  SurfaceSide side(const Vec3& p) const;
  bool strictly_inside(const Vec3& p) const { return side(p) == SurfaceSide::inside; }
  // Squared distance from p to the surface, m^2.
  double squared_distance(const Vec3& p) const;
  // Index (into faces()) of the triangle holding the surface point nearest to p; that point in
  // *closest when given. hint: a face near the answer (e.g. the same point's answer a step
  // before), whose centroid seeds CGAL's search instead of the tree's kd-tree (not built then:
  // its construction is most of a query-light step's cost); -1: none. The answer is exact either
  // way (the seed only bounds the first search radius).
  int closest_face(const Vec3& p, Vec3* closest = nullptr, int hint = -1) const;
  // Unit outward normal of face f at the current positions (zero for a collapsed face).
  Vec3 face_normal(int f) const;
  // The crossings of segment [a, b] with the surface in order along it (exact segment-triangle
  // predicates choose the faces; their parameters are computed in double). Crossings at one point
  // (an edge or a vertex shared by faces) are merged into one, their normals averaged; a
  // segment that only grazes the surface may still report one: callers reconcile with side().
  void crossings(const Vec3& a, const Vec3& b, std::vector<SurfaceCrossing>& out) const;
  // Bounding box of the current vertices.
  void bounds(Vec3& lo, Vec3& hi) const;
  // Faces collapsed (is_degenerate) at the last update: distances to them are taken to their
  // edges in double arithmetic, not by CGAL (whose projection onto them is NaN).
  int num_degenerate_faces() const;

  struct Impl;
  const Impl& impl() const { return *impl_; }

 private:
  std::unique_ptr<Impl> impl_;
};

// A triangle whose normal vanishes numerically (relative to its longest edge), or with a NaN.
bool is_degenerate(const Vec3& a, const Vec3& b, const Vec3& c);

// Whether two updated surfaces intersect (any pair of triangles meets, touching included), with
// PMP::do_intersect. With bounded_sides, a surface wholly inside the other counts too.
bool surfaces_intersect(const CgalSurface& a, const CgalSurface& b, bool bounded_sides);

// One-shot helper: for each query point, whether it lies strictly inside the closed surface
// (V: #V positions, F: #F outward triangles). On the surface counts as outside.
std::vector<bool> inside_surface(const Points& V, const std::vector<Tri>& F, const Points& queries);

// "5.5.1"
std::string cgal_version();

}  // namespace harness
