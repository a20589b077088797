// CGAL types behind CgalSurface. Internal: included only by the (at most two) CGAL translation
// units under reference/, because CGAL headers cost tens of seconds of compile time each.
#pragma once

#include "reference/cgal_surface.hpp"

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Surface_mesh.h>

#include <optional>

namespace harness {
namespace cgal {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Mesh = CGAL::Surface_mesh<Point>;
using Primitive = CGAL::AABB_face_graph_triangle_primitive<Mesh>;
// The tree's boxes: each face's box at the tree's last build, grown by a margin (a readable
// property map, CGAL's AABB_traits BboxMap). The primitives read their points through the mesh,
// so while no vertex has moved farther than the margin since the build every face lies in its
// box and the hierarchy stays valid: queries are exact without a rebuild (CgalSurface::update).
struct GrownBoxes {
  using key_type = Mesh::Face_index;
  using value_type = CGAL::Bbox_3;
  using reference = const CGAL::Bbox_3&;
  using category = boost::readable_property_map_tag;
  const std::vector<CGAL::Bbox_3>* boxes = nullptr;
  friend reference get(const GrownBoxes& m, key_type f) { return (*m.boxes)[static_cast<std::size_t>(f)]; }
};
using TreeTraits = CGAL::AABB_traits<Kernel, Primitive, GrownBoxes>;
using Tree = CGAL::AABB_tree<TreeTraits>;
using SideOf = CGAL::Side_of_triangle_mesh<Mesh, Kernel, CGAL::Default, Tree>;

inline Point to_point(const Vec3& p) { return Point(p.x(), p.y(), p.z()); }
inline Vec3 to_vec(const Point& p) { return Vec3(p.x(), p.y(), p.z()); }

}  // namespace cgal

struct CgalSurface::Impl {
  Impl() : tree(cgal::TreeTraits(cgal::GrownBoxes{&boxes})), distance_tree(cgal::TreeTraits(cgal::GrownBoxes{&boxes})) {}
  Impl(const Impl&) = delete;
  Impl& operator=(const Impl&) = delete;
  cgal::Mesh mesh;  // vertex i and face f are index i and f of the topology given
  std::vector<Tri> faces;
  // The trees' boxes (cgal::GrownBoxes), the points they were built on and their margin (a
  // quarter of the mean edge at the first update): update() rebuilds the trees only when some
  // vertex has moved farther than the margin since (counted in `rebuilds`).
  std::vector<CGAL::Bbox_3> boxes;
  std::vector<Vec3> built_at;
  double margin = 0.0;
  long long rebuilds = 0;
  // Mutable: the kd-tree that seeds distance queries is built lazily on the first query after an
  // update (CGAL 5.5's build() does not rebuild it, and a stale seed can give a wrong distance).
  mutable cgal::Tree tree;
  mutable bool kd_ready = false;
  // Side_of_triangle_mesh caches the tree's bounding box when constructed: it is re-made after
  // every rebuild, or points that moved beyond the old box would read as outside.
  std::optional<cgal::SideOf> side_of;
  bool ready = false;
  // Distances are constructions: CGAL projects onto a triangle's supporting plane, which is NaN
  // for a (numerically) degenerate triangle, and the exact fallback of the next comparison then
  // aborts inside GMP. A deformed soft body can collapse triangles, so those are kept out of a
  // separate distance tree (built only when some exist) and measured as three segments instead.
  std::vector<int> degenerate;                 // faces collapsed at the last update
  std::vector<cgal::Mesh::Face_index> proper;  // the others, when `degenerate` is not empty
  mutable cgal::Tree distance_tree;
  mutable bool distance_kd_ready = false;
};

}  // namespace harness
