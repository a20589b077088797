// CGAL translation unit 1 of 2: surfaces, classification, distances, intersection tests.
#include "reference/cgal_surface.hpp"

#include "reference/cgal_types.hpp"

#include "core/geometry.hpp"

#include <CGAL/Polygon_mesh_processing/intersection.h>
#include <CGAL/boost/graph/helpers.h>
#include <CGAL/version_macros.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>
#include <stdexcept>

namespace harness {

namespace PMP = CGAL::Polygon_mesh_processing;
using cgal::Mesh;

CgalSurface::CgalSurface() : impl_(std::make_unique<Impl>()) {}
CgalSurface::~CgalSurface() = default;
CgalSurface::CgalSurface(CgalSurface&&) noexcept = default;
CgalSurface& CgalSurface::operator=(CgalSurface&&) noexcept = default;

void CgalSurface::set_topology(int n_vertices, const std::vector<Tri>& F) {
  if (n_vertices < 4 || F.size() < 4)
    throw std::invalid_argument("CgalSurface: a closed surface needs at least 4 vertices and 4 faces");
  Impl& s = *impl_;
  s.side_of.reset();
  s.tree.clear();
  s.kd_ready = false;
  s.ready = false;
  s.built_at.clear();
  s.margin = 0.0;
  s.rebuilds = 0;
  s.mesh.clear();
  s.faces = F;
  s.mesh.reserve(static_cast<Mesh::size_type>(n_vertices),
                 static_cast<Mesh::size_type>(3 * F.size() / 2),
                 static_cast<Mesh::size_type>(F.size()));
  for (int i = 0; i < n_vertices; ++i) s.mesh.add_vertex(cgal::Point(0, 0, 0));
  for (std::size_t f = 0; f < F.size(); ++f) {
    for (int k = 0; k < 3; ++k)
      if (F[f][k] < 0 || F[f][k] >= n_vertices)
        throw std::invalid_argument("CgalSurface: vertex index out of range in face " +
                                    std::to_string(f));
    const Mesh::Face_index fi = s.mesh.add_face(Mesh::Vertex_index(F[f][0]),
                                                Mesh::Vertex_index(F[f][1]),
                                                Mesh::Vertex_index(F[f][2]));
    // Face indices must stay equal to positions in F (closest_face() relies on it).
    if (fi == Mesh::null_face() || static_cast<std::size_t>(fi) != f)
      throw std::invalid_argument("CgalSurface: face " + std::to_string(f) +
                                  " breaks the 2-manifold surface");
  }
  if (!CGAL::is_closed(s.mesh) || !CGAL::is_triangle_mesh(s.mesh))
    throw std::invalid_argument("CgalSurface: the surface is not closed");
  s.tree.insert(CGAL::faces(s.mesh).first, CGAL::faces(s.mesh).second, s.mesh);
}

void CgalSurface::update(const Vec3* points) {
  Impl& s = *impl_;
  const int n = static_cast<int>(s.mesh.number_of_vertices());
  for (int i = 0; i < n; ++i) s.mesh.point(Mesh::Vertex_index(i)) = cgal::to_point(points[i]);
  // The hierarchy holds while every vertex is within the margin of where the boxes were made
  // (each face then inside its grown box); else it is rebuilt on boxes grown from the points now.
  bool rebuild = !s.ready || !(s.margin > 0.0) || static_cast<int>(s.built_at.size()) != n;
  for (int i = 0; i < n && !rebuild; ++i) rebuild = !((points[i] - s.built_at[i]).squaredNorm() <= s.margin * s.margin);
  if (rebuild) {
    if (!(s.margin > 0.0)) {  // a quarter of the mean edge, once
      double sum = 0.0;
      for (const Tri& t : s.faces)
        for (int k = 0; k < 3; ++k) sum += (points[t[(k + 1) % 3]] - points[t[k]]).norm();
      s.margin = s.faces.empty() ? 0.0 : 0.25 * sum / (3.0 * static_cast<double>(s.faces.size()));
    }
    s.built_at.assign(points, points + n);
    // Grown by the margin and a little more, so that rounding in the box never decides.
    const double g = std::isfinite(s.margin) ? s.margin * (1.0 + 1e-9) + 1e-300 : 0.0;
    s.boxes.resize(s.faces.size());
    for (std::size_t f = 0; f < s.faces.size(); ++f) {
      const Vec3 &a = points[s.faces[f][0]], &b = points[s.faces[f][1]], &c = points[s.faces[f][2]];
      const Vec3 lo = a.cwiseMin(b).cwiseMin(c).array() - g, hi = a.cwiseMax(b).cwiseMax(c).array() + g;
      s.boxes[f] = CGAL::Bbox_3(lo.x(), lo.y(), lo.z(), hi.x(), hi.y(), hi.z());
    }
    s.side_of.reset();
    s.tree.build();
    s.side_of.emplace(s.tree);  // it keeps the tree's box: re-made with every build
    ++s.rebuilds;
  }
  s.tree.do_not_accelerate_distance_queries();  // drops the kd-tree of old points
  s.kd_ready = false;

  s.degenerate.clear();
  s.proper.clear();
  for (int f = 0; f < static_cast<int>(s.faces.size()); ++f)
    if (is_degenerate(points[s.faces[f][0]], points[s.faces[f][1]], points[s.faces[f][2]]))
      s.degenerate.push_back(f);
  s.distance_tree.clear();
  s.distance_kd_ready = false;
  if (!s.degenerate.empty()) {
    std::size_t next = 0;
    for (int f = 0; f < static_cast<int>(s.faces.size()); ++f) {
      if (next < s.degenerate.size() && s.degenerate[next] == f) {
        ++next;
        continue;
      }
      s.proper.push_back(Mesh::Face_index(static_cast<Mesh::size_type>(f)));
    }
    if (!s.proper.empty()) {
      s.distance_tree.insert(s.proper.begin(), s.proper.end(), s.mesh);
      s.distance_tree.build();
      s.distance_tree.do_not_accelerate_distance_queries();
    }
  }
  s.ready = true;
}

long long CgalSurface::tree_rebuilds() const { return impl_->rebuilds; }

int CgalSurface::num_vertices() const { return static_cast<int>(impl_->mesh.number_of_vertices()); }
const std::vector<Tri>& CgalSurface::faces() const { return impl_->faces; }
bool CgalSurface::ready() const { return impl_->ready; }

SurfaceSide CgalSurface::side(const Vec3& p) const {
  switch ((*impl_->side_of)(cgal::to_point(p))) {
    case CGAL::ON_BOUNDED_SIDE: return SurfaceSide::inside;
    case CGAL::ON_BOUNDARY: return SurfaceSide::boundary;
    default: return SurfaceSide::outside;
  }
}

namespace {

// Nearest surface point to p: face index, point, squared distance.
struct Nearest {
  int face = -1;
  Vec3 point = Vec3::Zero();
  double d2 = std::numeric_limits<double>::infinity();
};

Nearest nearest(const CgalSurface::Impl& s, const Vec3& p, int hint) {
  Nearest n;
  const bool split = !s.degenerate.empty();
  cgal::Tree& tree = split ? s.distance_tree : s.tree;  // mutable members: the kd-tree is lazy
  bool& kd_ready = split ? s.distance_kd_ready : s.kd_ready;
  // A hint seeds the search with a point on a proper face (in the tree searched).
  const bool hinted = hint >= 0 && hint < static_cast<int>(s.faces.size()) &&
                      !std::binary_search(s.degenerate.begin(), s.degenerate.end(), hint);
  if (!tree.empty()) {
    cgal::Tree::Point_and_primitive_id seed;
    if (hinted) {
      // The point of the hinted face closest to p: a tight first radius, so the traversal prunes
      // nearly everything (a far centroid would leave most of the tree to visit).
      const Tri& t = s.faces[hint];
      const Vec3 c = closest_on_triangle(p, cgal::to_vec(s.mesh.point(Mesh::Vertex_index(t[0]))),
                                         cgal::to_vec(s.mesh.point(Mesh::Vertex_index(t[1]))),
                                         cgal::to_vec(s.mesh.point(Mesh::Vertex_index(t[2]))));
      seed = {cgal::to_point(c), Mesh::Face_index(static_cast<Mesh::size_type>(hint))};
    } else if (!kd_ready) {
      tree.accelerate_distance_queries();
      kd_ready = true;
    }
    const auto pp = hinted ? tree.closest_point_and_primitive(cgal::to_point(p), seed)
                           : tree.closest_point_and_primitive(cgal::to_point(p));
    n.face = static_cast<int>(pp.second);
    n.point = cgal::to_vec(pp.first);
    n.d2 = (n.point - p).squaredNorm();
  }
  for (int f : s.degenerate) {
    const Tri& t = s.faces[f];
    for (int k = 0; k < 3; ++k) {
      const Vec3 q = closest_on_segment(p, cgal::to_vec(s.mesh.point(Mesh::Vertex_index(t[k]))),
                                        cgal::to_vec(s.mesh.point(Mesh::Vertex_index(t[(k + 1) % 3]))));
      const double d2 = (q - p).squaredNorm();
      if (d2 < n.d2) n = Nearest{f, q, d2};
    }
  }
  return n;
}

}  // namespace

double CgalSurface::squared_distance(const Vec3& p) const { return nearest(*impl_, p, -1).d2; }

int CgalSurface::closest_face(const Vec3& p, Vec3* closest, int hint) const {
  const Nearest n = nearest(*impl_, p, hint);
  if (closest) *closest = n.point;
  return n.face;
}

Vec3 CgalSurface::face_normal(int f) const {
  const Impl& s = *impl_;
  const Tri& t = s.faces[static_cast<std::size_t>(f)];
  const Vec3 p0 = cgal::to_vec(s.mesh.point(Mesh::Vertex_index(t[0])));
  const Vec3 n = (cgal::to_vec(s.mesh.point(Mesh::Vertex_index(t[1]))) - p0)
                     .cross(cgal::to_vec(s.mesh.point(Mesh::Vertex_index(t[2]))) - p0);
  const double len = n.norm();
  return len > 0.0 && std::isfinite(len) ? Vec3(n / len) : Vec3(Vec3::Zero());
}

void CgalSurface::crossings(const Vec3& a, const Vec3& b, std::vector<SurfaceCrossing>& out) const {
  out.clear();
  const Impl& s = *impl_;
  const Vec3 d = b - a;
  if (s.tree.empty() || !(d.squaredNorm() > 0.0)) return;
  const cgal::Kernel::Segment_3 seg(cgal::to_point(a), cgal::to_point(b));
  std::vector<cgal::Tree::Primitive_id> faces;
  s.tree.all_intersected_primitives(seg, std::back_inserter(faces));
  for (const auto fd : faces) {
    const int f = static_cast<int>(fd);
    const Tri& t = s.faces[static_cast<std::size_t>(f)];
    const Vec3 p0 = cgal::to_vec(s.mesh.point(Mesh::Vertex_index(t[0])));
    const Vec3 n = face_normal(f);
    const double den = n.dot(d);
    // Along a face's plane (or a collapsed face): the middle of the segment stands for the point.
    const double tt = std::fabs(den) > 0.0 ? n.dot(p0 - a) / den : 0.5;
    out.push_back({std::clamp(std::isfinite(tt) ? tt : 0.5, 0.0, 1.0), n});
  }
  std::sort(out.begin(), out.end(), [](const SurfaceCrossing& x, const SurfaceCrossing& y) { return x.t < y.t; });
  // One point shared by several faces (an edge, a vertex) is one crossing.
  constexpr double kSame = 1e-9;
  std::size_t k = 0;
  for (std::size_t i = 0; i < out.size(); ++i) {
    if (k > 0 && out[i].t - out[k - 1].t <= kSame) {
      out[k - 1].normal += out[i].normal;
      continue;
    }
    out[k++] = out[i];
  }
  out.resize(k);
  for (SurfaceCrossing& c : out) {
    const double len = c.normal.norm();
    c.normal = len > 0.0 ? Vec3(c.normal / len) : Vec3(Vec3::Zero());
  }
}

int CgalSurface::num_degenerate_faces() const { return static_cast<int>(impl_->degenerate.size()); }

bool is_degenerate(const Vec3& a, const Vec3& b, const Vec3& c) {
  // Twice the area against the longest edge squared: a relative sine below 1e-12 (or a NaN)
  // counts as collapsed. Far below any triangle a simulation would keep on purpose.
  const double n2 = (b - a).cross(c - a).squaredNorm();
  const double e2 = std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
  return !(n2 > 1e-24 * e2 * e2) || !(e2 > 0.0);
}

void CgalSurface::bounds(Vec3& lo, Vec3& hi) const {
  lo = Vec3::Constant(std::numeric_limits<double>::infinity());
  hi = -lo;
  for (const auto v : impl_->mesh.vertices()) {
    const Vec3 q = cgal::to_vec(impl_->mesh.point(v));
    lo = lo.cwiseMin(q);
    hi = hi.cwiseMax(q);
  }
}

bool surfaces_intersect(const CgalSurface& a, const CgalSurface& b, bool bounded_sides) {
  return PMP::do_intersect(a.impl().mesh, b.impl().mesh,
                           CGAL::parameters::do_overlap_test_of_bounded_sides(bounded_sides));
}

std::vector<bool> inside_surface(const Points& V, const std::vector<Tri>& F, const Points& queries) {
  CgalSurface s;
  s.set_topology(static_cast<int>(V.size()), F);
  s.update(V.data());
  std::vector<bool> in(queries.size());
  for (std::size_t i = 0; i < queries.size(); ++i) in[i] = s.strictly_inside(queries[i]);
  return in;
}

std::string cgal_version() { return CGAL_VERSION_STR; }

}  // namespace harness
