// voxel_exact's narrow phase on a device (contact_kernels.hpp says how the bodies are shared): the
// closest point of a candidate triangle with its feature (voxel_exact_geometry.hpp), the
// angle-weighted pseudonormal, the candidates of a node's 3 x 3 x 3 block in voxel_exact's order,
// and the push of a node found inside. Included by contact_kernels.hpp alone, where its types are
// declared (DirView, Push, cell_range, set_line).
#pragma once

namespace harness::dev {

// The closest point of a triangle and of its edges: closest_kernels.hpp (the CPU's too).
HARNESS_HD inline V3 face_cross(const DirView& D, const double* x, int f) {
  const int* t = D.faces + 3 * f;
  const V3 a = load3(x, D.host_begin + t[0]);
  return cross(load3(x, D.host_begin + t[1]) - a, load3(x, D.host_begin + t[2]) - a);
}
HARNESS_HD inline V3 unit_face_normal(const DirView& D, const double* x, int f) {
  const V3 n = face_cross(D, x, f);
  const double len = norm(n);
  return len > 0.0 && isfinite(len) ? n / len : V3{0.0, 0.0, 0.0};
}
HARNESS_HD inline V3 pseudonormal(const DirView& D, const double* x, int face, int feature) {
  if (feature == kInteriorFeature) return face_cross(D, x, face);
  if (feature >= 3) return unit_face_normal(D, x, face) + unit_face_normal(D, x, D.adjacent[3 * face + (feature - 3)]);
  const int u = D.faces[3 * face + feature];
  const V3 xu = load3(x, D.host_begin + u);
  V3 n{0.0, 0.0, 0.0};
  for (int k = D.vf_start[u]; k < D.vf_start[u + 1]; ++k) {
    const int* t = D.faces + 3 * D.vf_faces[k];
    const int j = t[0] == u ? 0 : t[1] == u ? 1 : 2;
    const V3 e1 = load3(x, D.host_begin + t[(j + 1) % 3]) - xu, e2 = load3(x, D.host_begin + t[(j + 2) % 3]) - xu;
    const V3 c = cross(e1, e2);
    const double len = norm(c);
    if (!(len > 0.0) || !isfinite(len)) continue;
    n = n + (atan2(len, dot(e1, e2)) / len) * c;
  }
  return n;
}

// The squared distance from p to the box of face f's vertices (voxel_exact_geometry.hpp's
// box_bounds): a lower bound of the distance to the face.
HARNESS_HD inline double face_bound(const DirView& D, const double* x, int f, V3 p) {
  const int* t = D.faces + 3 * f;
  const V3 a = load3(x, D.host_begin + t[0]), b = load3(x, D.host_begin + t[1]), c = load3(x, D.host_begin + t[2]);
  const double pa[3] = {p.x, p.y, p.z}, A[3] = {a.x, a.y, a.z}, B[3] = {b.x, b.y, b.z}, C[3] = {c.x, c.y, c.z};
  double d2[3];
  for (int k = 0; k < 3; ++k) {
    const double bc_lo = C[k] < B[k] ? C[k] : B[k], bc_hi = B[k] < C[k] ? C[k] : B[k];
    const double lo = bc_lo < A[k] ? bc_lo : A[k], hi = A[k] < bc_hi ? bc_hi : A[k];
    double d = lo - pa[k], e = pa[k] - hi;
    d = d > e ? d : e;
    d = d > 0.0 ? d : 0.0;
    d2[k] = d * d;
  }
  return d2[0] + d2[1] + d2[2];
}

// Calls fn(face) for every candidate of the block around ijk: the faces incident to the vertices
// listed in its voxels (z, y, x order, nodes in increasing order, each vertex's faces in order; a
// face may come more than once: the first time is its place in voxel_exact's candidate order).
template <class Fn>
HARNESS_HD inline void for_candidates(const DirView& D, const int ijk[3], Fn&& fn) {
  for_block_nodes(D, ijk, [&](int node) {
    const int u = node - D.host_begin;
    for (int k = D.vf_start[u]; k < D.vf_start[u + 1]; ++k) fn(D.vf_faces[k]);
  });
}

// A candidate face's closest point to p (voxel_exact's evaluate): squared distance, feature,
// point and barycentric weights.
struct Nearest {
  double d2 = INFINITY;
  int face = -1, feature = 0;
  V3 q{0.0, 0.0, 0.0};
  double w[3] = {1.0, 0.0, 0.0};
};
HARNESS_HD inline Nearest eval_candidate(const DirView& D, const double* x, int f, V3 p) {
  const int* t = D.faces + 3 * f;
  V3 v[3];
  Nearest n;
  for (int j = 0; j < 3; ++j) v[j] = load3(x, D.host_begin + t[j]);
  if (!closest_feature(p, v[0], v[1], v[2], n.q, n.w, n.feature)) closest_on_edges(p, v, n.q, n.w, n.feature);
  n.d2 = sqnorm(n.q - p);
  n.face = f;
  return n;
}

// The push of a guest node g whose nearest candidate is n: inside by the pseudonormal (false:
// outside, or on the surface), depth, direction; the line rule's host or the contact point's
// triangle (penalty).
HARNESS_HD inline bool exact_contact(const DirView& D, const double* x, int g, const Nearest& best, Push& P) {
  const V3 p = load3(x, g);
  if (best.face < 0 || !isfinite(best.d2)) return false;
  const V3 N = pseudonormal(D, x, best.face, best.feature);
  if (!(dot(p - best.q, N) < 0.0)) return false;
  const double d = sqrt(best.d2);
  V3 n;
  if (d > 1e-12 * (1.0 + norm(p)) && isfinite(d)) {
    n = (best.q - p) / d;
  } else {
    const double len = norm(N);
    n = len > 0.0 && isfinite(len) ? N / len : unit_face_normal(D, x, best.face);
  }
  const int* t = D.faces + 3 * best.face;
  if (D.force_rule == kForcePenalty) {  // penalty_depth: the contact point's triangle
    P.count = 3;
    for (int j = 0; j < 3; ++j) P.hosts[j] = D.host_begin + t[j], P.w[j] = best.w[j];
    P.n[0] = n.x, P.n[1] = n.y, P.n[2] = n.z;
    P.mag = d;
    return true;
  }
  int near = -1;  // triangle_vertices_nearest_first, k = 1
  double e = 0.0;
  for (int j = 0; j < 3; ++j) {
    const int node = D.host_begin + t[j];
    const double dd = sqnorm(load3(x, node) - p);
    if (near < 0 || dd < e || (dd == e && node < near)) near = node, e = dd;
  }
  set_line(P, near, n);
  return true;
}

// Whether the guest node at p is a candidate of voxel_exact at all: strictly inside the host's box.
HARNESS_HD inline bool in_host_box(const GridState& G, V3 p) {
  return p.x > G.host_lo[0] && p.y > G.host_lo[1] && p.z > G.host_lo[2] && p.x < G.host_hi[0] && p.y < G.host_hi[1] &&
         p.z < G.host_hi[2];
}

// voxel_exact's contact: the nearest host triangle among those incident to the vertices listed in
// the node's 3 x 3 x 3 block, in voxel_exact's order: the candidate of the least box bound first
// (ties: the first in candidate order), then every other whose bound is below the best distance so
// far, a closer one replacing it. That selects the least distance m, and among the candidates at m
// the least-bound one if it is at m, else the first in candidate order (any candidate at m before
// the winner would have been evaluated: its bound <= m < the best so far): the rule the GPU's warp
// search applies (cuda_step.cu). False: no contact.
HARNESS_HD inline bool voxel_exact_push(const DirView& D, const double* x, int g, const int ijk[3], Push& P) {
  const V3 p = load3(x, g);
  int first = -1;
  double first_bound = INFINITY;
  for_candidates(D, ijk, [&](int f) {
    const double b = face_bound(D, x, f, p);
    if (first < 0 || b < first_bound) first = f, first_bound = b;
  });
  if (first < 0) return false;
  Nearest best = eval_candidate(D, x, first, p);
  for_candidates(D, ijk, [&](int f) {
    if (f != first && face_bound(D, x, f, p) < best.d2) {
      const Nearest c = eval_candidate(D, x, f, p);
      if (c.d2 < best.d2) best = c;
    }
  });
  return exact_contact(D, x, g, best, P);
}

}  // namespace harness::dev
