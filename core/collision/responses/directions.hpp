// The direction rules of the paper's two penalty eliminators (line.hpp, plane.hpp; Newton's third
// law: every contact's forces sum to zero). F is the force magnitude in N, given per contact by
// the force rule (force_rule.hpp); forces are added into World::f.
//
// Host outward hint at a host node (host_outward_hint): for a host surface vertex (body-local
// index < n_surface, with faces) the area-weighted vertex normal; for an interior node, or a
// surface vertex whose normal vanishes, the direction from the host's bounding-box centre to the
// node. Hints are normalised; a hint may be zero (node at the centre).
//
// line  (the paper's rule) n = the unit vector from the nearest host node h of the guest's voxel
//       to the guest node g; +F n on g, -F n on h. With an exact detector (cgal, fcl) that
//       knows the outward direction (CollisionDetector::contact_direction), n is that direction
//       instead: the nearest host vertex is inside the contact's own triangle, and the line to
//       it points inward for a guest node that is already inside.
//       Fallbacks, in order, when g and h coincide (zero-length line):
//         the host's outward hint at h; then the direction from the host's box centre to g;
//         then +z.
// plane (the paper's rule for the expanding implant) the three nearest host nodes h0, h1, h2
//       from the guest's voxel and its 26 neighbours span a plane with unit normal n; +F n on g
//       and -F/3 n on each of h0, h1, h2.
//       Orientation: the guest must be pushed toward the host's outside, so n is flipped to
//       agree with the sum of the (normalised) outward hints at h0, h1, h2; when that sum is
//       perpendicular to n (or zero), with the direction from the host's box centre to the
//       plane's centroid; when that is perpendicular too, n is kept as the cross product gives it.
//       Fallbacks: fewer than three host nodes in the neighbourhood, or collinear or
//       near-collinear points (|(h1 - h0) x (h2 - h0)| < 1e-12 s^2, s the largest distance among
//       them) -> the line rule with the nearest node h0.
// orient (ContactSpec): `paper` as above; `guest` orients the plane's normal toward the guest
// node (hint: guest node - centroid, then guest node - h0) as the line is; `outward` flips the
// line's direction to agree with the host's outward hint at h (the plane as the paper's).
// The host's box centre is recomputed from the positions once per eliminate() call (always for
// plane, only when a degenerate contact needs it for line): eliminators work with any detector.
// A contact for which the detector reports no host node at all gets no force (the voxel
// detector always reports one). Directions are always finite unit vectors, so forces are finite
// whenever F is.
#pragma once

#include "core/collision/responses/collision_eliminator.hpp"
#include "core/world.hpp"

#include <cmath>

namespace harness {

// a / |a| when that is a finite unit vector (|a| rescaled first when it overflows), else zero.
// Inline: the eliminators call it once per contact.
Vec3 unit_or_zero_rescaled(const Vec3& a);
inline Vec3 unit_or_zero(const Vec3& a) {
  const double n = a.norm();
  if (!(n > 0.0) || !std::isfinite(n)) return unit_or_zero_rescaled(a);
  const Vec3 u = a / n;
  return std::isfinite(u.x()) && std::isfinite(u.y()) && std::isfinite(u.z()) ? u : Vec3::Zero();
}
// Centre of the host's current bounding box.
Vec3 host_center_of(const World& w, int host);

// The penalty rule's depth (Push::normal, Push::depth) of a push whose host nodes are set, and
// the reaction's weights at the point it is measured from, so that the penalty is the gradient
// of 1/2 k depth^2 (conservative) while the host nodes stay the same:
//   exact detector  the closest point of the host surface (CollisionDetector::contact_point):
//                   its triangle's vertices take the reaction by barycentric weights;
//   plane push      the plane's normal n, depth (x_h0 - x_g) . n, the reaction by the barycentric
//                   weights of the closest point of the triangle h0 h1 h2 (not a third each);
//   line push       the host's outward hint at its node, depth (x_h - x_g) . hint.
// `host_center` as for host_outward_hint.
void penalty_depth(const World& w, int host, const CollisionDetector& det, const Contact& c, const Vec3& host_center,
                   Push& p);

// Normalised outward hint of global host node `node` of body `host` (see above); may be zero.
Vec3 host_outward_hint(const World& w, int host, int node, const Vec3& host_center);

// Unit direction of the line rule (force on the guest node), with its fallbacks.
Vec3 line_direction(const World& w, int host, int guest_node, int host_node,
                    const Vec3& host_center);

// Unit normal of the plane through p0, p1, p2, oriented to agree with `hint` (or, when the hint
// is perpendicular, with `second_hint`). Returns false, leaving n untouched, when the points are
// (near-)collinear as defined above.
bool plane_normal(const Vec3& p0, const Vec3& p1, const Vec3& p2, const Vec3& hint,
                  const Vec3& second_hint, Vec3& n);

}  // namespace harness
