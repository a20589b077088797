#include "reference/exact_detectors.hpp"

#include "core/collision/detectors/triangles.hpp"
#include "core/geometry.hpp"

#include <cmath>

#include <algorithm>
#include <limits>
#include <stdexcept>

namespace harness {

namespace {

// Exact predicates on a NaN abort the program inside GMP: a diverged state gets no contacts
// (the run's finiteness check then stops it).
bool all_finite(const World& w, const Body& b) {
  for (int i = b.begin; i < b.end; ++i)
    if (!w.x[i].allFinite()) return false;
  return true;
}

}  // namespace

// ---- CGAL -----------------------------------------------------------------------------------

void CgalDetector::initialize(const World& w, const ContactSpec& spec) {
  const Body& H = w.bodies.at(spec.host);
  host_ = spec.host;
  guest_ = spec.guest;
  host_begin_ = H.begin;
  host_surface_.set_topology(H.n_surface, H.faces);
  guest_begin_ = w.bodies.at(spec.guest).begin;
  last_face_.assign(static_cast<std::size_t>(w.bodies.at(spec.guest).size()), -1);
}

void CgalDetector::detect(const World& w, std::vector<Contact>& out) {
  out.clear();
  const Body& H = w.bodies[host_];
  const Body& G = w.bodies[guest_];
  if (!all_finite(w, H) || !all_finite(w, G)) return;
  host_surface_.update(&w.x[H.begin]);  // CGAL 5.5's AABB tree has no refit: rebuilt (measured)
  for (int i = G.begin; i < G.end; ++i) {
    if (!host_surface_.strictly_inside(w.x[i])) continue;
    int& last = last_face_[i - G.begin];
    last = host_surface_.closest_face(w.x[i], nullptr, last);
    out.push_back(Contact{i, last});
  }
}

bool CgalDetector::contact_point(const World& w, const Contact& c, ContactPoint& out) const {
  if (c.key < 0 || c.key >= static_cast<int>(host_surface_.faces().size())) return false;
  return triangle_contact_point(w, host_begin_, host_surface_.faces()[c.key], w.x[c.guest], out);
}

int CgalDetector::nearest_hosts(const World& w, const Contact& c, int k, int* out) const {
  if (c.key < 0 || c.key >= static_cast<int>(host_surface_.faces().size())) return 0;
  return triangle_vertices_nearest_first(w, host_begin_, host_surface_.faces()[c.key], w.x[c.guest],
                                         k, out);
}


bool CgalDetector::contact_direction(const World& w, const Contact& c, Vec3& n) const {
  if (c.key < 0 || c.key >= static_cast<int>(host_surface_.faces().size())) return false;
  return triangle_direction(w, host_begin_, host_surface_.faces()[c.key], w.x[c.guest], n);
}

// ---- FCL ------------------------------------------------------------------------------------

void FclDetector::initialize(const World& w, const ContactSpec& spec) {
  const Body& H = w.bodies.at(spec.host);
  const Body& G = w.bodies.at(spec.guest);
  host_body_ = spec.host;
  guest_body_ = spec.guest;
  host_begin_ = H.begin;
  host_.set_topology(H.n_surface, H.faces);
  guest_.set_topology(G.n_surface, G.faces);
  best_d2_.assign(G.n_surface, std::numeric_limits<double>::infinity());
  best_tri_.assign(G.n_surface, -1);
  touched_.clear();
  touched_.reserve(G.n_surface);
}

void FclDetector::detect(const World& w, std::vector<Contact>& out) {
  out.clear();
  const Body& H = w.bodies[host_body_];
  const Body& G = w.bodies[guest_body_];
  if (!all_finite(w, H) || !all_finite(w, G)) return;
  host_.update(&w.x[H.begin]);
  guest_.update(&w.x[G.begin]);
  intersecting_pairs(guest_, host_, pairs_, /*with_depth=*/false);
  const auto& gf = guest_.faces();
  const auto& hf = host_.faces();
  for (const TrianglePair& p : pairs_) {
    const Tri& ht = hf[p.b];
    for (int v : gf[p.a]) {
      const Vec3& x = w.x[G.begin + v];
      const double d2 =
          (closest_on_triangle(x, w.x[H.begin + ht[0]], w.x[H.begin + ht[1]], w.x[H.begin + ht[2]]) - x)
              .squaredNorm();
      if (best_tri_[v] < 0) touched_.push_back(v);
      if (best_tri_[v] < 0 || d2 < best_d2_[v] || (d2 == best_d2_[v] && p.b < best_tri_[v])) {
        best_d2_[v] = d2;
        best_tri_[v] = p.b;
      }
    }
  }
  std::sort(touched_.begin(), touched_.end());  // deterministic order: by node
  for (int v : touched_) {
    out.push_back(Contact{G.begin + v, best_tri_[v]});
    best_tri_[v] = -1;
    best_d2_[v] = std::numeric_limits<double>::infinity();
  }
  touched_.clear();
}

int FclDetector::nearest_hosts(const World& w, const Contact& c, int k, int* out) const {
  if (c.key < 0 || c.key >= static_cast<int>(host_.faces().size())) return 0;
  return triangle_vertices_nearest_first(w, host_begin_, host_.faces()[c.key], w.x[c.guest], k, out);
}

bool FclDetector::contact_direction(const World& w, const Contact& c, Vec3& n) const {
  if (c.key < 0 || c.key >= static_cast<int>(host_.faces().size())) return false;
  return face_normal(w, host_begin_, host_.faces()[c.key], n);
}

bool FclDetector::contact_point(const World& w, const Contact& c, ContactPoint& out) const {
  if (c.key < 0 || c.key >= static_cast<int>(host_.faces().size())) return false;
  // FCL reports the vertices of intersecting triangles, inside or not: the depth is signed.
  return triangle_contact_point(w, host_begin_, host_.faces()[c.key], w.x[c.guest], out, false);
}

std::unique_ptr<CollisionDetector> make_exact_detector(const std::string& name) {
  if (name == "cgal") return std::make_unique<CgalDetector>();
  if (name == "fcl") return std::make_unique<FclDetector>();
  throw std::invalid_argument("detector \"" + name + "\" is not an exact detector");
}

}  // namespace harness
