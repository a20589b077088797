// The volume two bodies share and its gradient with respect to their surface vertices, by layered
// depth images (LDI: Faure, Barbier, Allard, Falipou, "Image-based collision detection and response
// between arbitrary volumetric objects", SCA 2008): the practical bound of a restriction method.
//
// Along each axis k (u, v the other two, in cyclic order), a grid of square pixels of edge `pixel`
// covers the overlap of the two surfaces' bounding boxes in the (u, v) plane. Every triangle of
// both closed, outward-oriented surfaces is rasterised at the pixel centres (a centre on an edge
// goes to one triangle only: the top-left rule); where the pixel's ray along +k crosses it, a
// fragment records its depth (the barycentric blend of the triangle's vertices' k coordinates)
// and whether the ray enters the body there (the outward normal's k component negative) or leaves
// it. Per pixel the fragments in depth order give each body's winding number; the ray is inside
// both where both are positive. V_k = pixel^2 * the length inside both, summed over the pixels.
// Moving a fragment that opens a shared interval by dz changes V_k by -pixel^2 dz, one that closes
// it by +pixel^2 dz; through the barycentric weights this is the gradient of V_k with respect to
// the k coordinates of the triangle's vertices. The volume is the mean of V_x, V_y, V_z; the
// gradient's k component comes from axis k's image (as in Faure et al.).
//
// Exactness: V_k is exact for the polyhedra up to the sampling of the (u, v) plane at the pixel
// centres (a prism per pixel); its derivative along k is exact (moving a vertex along k changes no
// pixel's coverage), so a finite difference along k reproduces the gradient. The gradient sums to
// zero over all vertices of both bodies (a translation changes no V_k).
#pragma once

#include "core/world.hpp"

#include <vector>

namespace harness {

struct IntersectionVolume {
  double volume = 0.0;                  // m^3: the mean of per_axis
  double per_axis[3] = {0.0, 0.0, 0.0};  // V_x, V_y, V_z, m^3
  // dV/dx per surface vertex of the two bodies (body-local surface index), component k from V_k.
  std::vector<Vec3> grad_a, grad_b;
  long long pixels = 0;     // pixels rasterised over the three images
  long long fragments = 0;  // fragments over the three images
};

// The LDI of bodies a and b of `w` at positions x, with square pixels of edge `pixel` (m, > 0).
// Bodies without a closed surface (no faces) share no volume.
IntersectionVolume intersection_volume(const World& w, const Points& x, int a, int b, double pixel);

}  // namespace harness
