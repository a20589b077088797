// What detectors that find the host triangle of a contact (the exact ones, spatial hashing)
// answer about it: its vertices nearest first, its outward normal, the closest point.
#pragma once

#include "core/collision/detectors/collision_detector.hpp"

namespace harness {

// The (up to 3) vertices of host triangle t, as global indices, nearest to p first.
int triangle_vertices_nearest_first(const World& w, int host_begin, const Tri& t, const Vec3& p, int k, int* out);
// Outward unit normal of host triangle t (global node offset `begin`); false when degenerate.
bool face_normal(const World& w, int begin, const Tri& t, Vec3& n);
// The closest point of host triangle t to x: barycentric weights on its vertices, the outward
// normal, and x's depth: its distance to that point when the detector knows x is inside the
// host (inside = true), else that distance signed by the side of the face x is on (negative in
// front of it: no penetration).
bool triangle_contact_point(const World& w, int begin, const Tri& t, const Vec3& x, ContactPoint& out,
                            bool inside = true);
// Per face f and edge k (t[k], t[k + 1]): the face across that edge (3 F entries; f itself where
// no face shares the edge the other way round).
std::vector<int> edge_adjacency(const std::vector<Tri>& faces);
// The angle-weighted pseudonormal of surface vertex u (Baerentzen and Aanaes 2005): its incident
// faces' normals (vf_start / vf_faces, CSR over body-local vertices) weighted by their angles at
// it; not normalised.
Vec3 vertex_pseudonormal(const World& w, int begin, const std::vector<Tri>& faces, const std::vector<int>& vf_start,
                         const std::vector<int>& vf_faces, int u);
// The direction from x to the closest point of t (outward for a node inside), or the face's
// normal when x lies on it; false when degenerate.
bool triangle_direction(const World& w, int begin, const Tri& t, const Vec3& x, Vec3& n);

}  // namespace harness
