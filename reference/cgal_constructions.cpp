// CGAL translation unit 2 of 2: corefinement volume and convex hulls.
#include "reference/cgal_constructions.hpp"

#include "reference/cgal_types.hpp"

#include <CGAL/Polygon_mesh_processing/corefinement.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/boost/graph/helpers.h>
#include <CGAL/convex_hull_3.h>

#include <exception>

namespace harness {

namespace PMP = CGAL::Polygon_mesh_processing;
using cgal::Mesh;

bool intersection_volume(const CgalSurface& a, const CgalSurface& b, double& volume) {
  volume = 0.0;
  if (!surfaces_intersect(a, b, /*bounded_sides=*/true)) return true;
  try {
    // Corefinement requires inputs free of self-intersections and collapsed faces, which a
    // deformed soft body need not be: refuse rather than return a wrong number.
    if (a.num_degenerate_faces() > 0 || b.num_degenerate_faces() > 0 ||
        PMP::does_self_intersect(a.impl().mesh) || PMP::does_self_intersect(b.impl().mesh))
      return false;
    Mesh ma = a.impl().mesh, mb = b.impl().mesh, out;  // corefinement modifies its inputs
    if (!PMP::corefine_and_compute_intersection(ma, mb, out)) return false;
    if (out.number_of_faces() == 0) return true;  // the regions only touch
    if (!CGAL::is_closed(out)) return false;
    volume = CGAL::to_double(PMP::volume(out));
    return volume >= 0.0;
  } catch (const std::exception&) {
    volume = 0.0;
    return false;
  }
}

bool convex_hull(const Vec3* points, int n, Points& V, std::vector<Tri>& F) {
  V.clear();
  F.clear();
  if (n < 4) return false;
  std::vector<cgal::Point> pts;
  pts.reserve(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) pts.push_back(cgal::to_point(points[i]));
  Mesh hull;
  CGAL::convex_hull_3(pts.begin(), pts.end(), hull);
  if (hull.number_of_faces() < 4 || !CGAL::is_closed(hull) || !CGAL::is_triangle_mesh(hull))
    return false;
  // Compact indices: the hull mesh need not number its vertices 0..n-1.
  auto index = hull.add_property_map<Mesh::Vertex_index, int>("v:harness_index", -1).first;
  for (const auto v : hull.vertices()) {
    index[v] = static_cast<int>(V.size());
    V.push_back(cgal::to_vec(hull.point(v)));
  }
  for (const auto f : hull.faces()) {
    Tri t{};
    int k = 0;
    for (const auto v : CGAL::vertices_around_face(hull.halfedge(f), hull)) t[k++] = index[v];
    F.push_back(t);
  }
  return true;
}

}  // namespace harness
