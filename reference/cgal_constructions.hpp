// CGAL constructions that the per-step ground truth does not need: the penetration volume by
// corefinement (optional, slow) and convex hulls (for the libccd reference). Compiled apart from
// cgal_surface.cpp because corefinement alone costs as much compile time as all the rest.
#pragma once

#include "reference/cgal_surface.hpp"

namespace harness {

// Volume (m^3) of the intersection of the regions bounded by two updated surfaces, by
// PMP::corefine_and_compute_intersection on copies. Returns false when CGAL cannot give it:
// a self-intersecting input, a result that is not a closed volume, or an exception. Disjoint
// regions give true and 0 without corefining.
bool intersection_volume(const CgalSurface& a, const CgalSurface& b, double& volume);

// Convex hull of points[0..n): hull vertices V and outward triangles F over them (both
// overwritten, capacity kept). Returns false when the points span less than three dimensions.
bool convex_hull(const Vec3* points, int n, Points& V, std::vector<Tri>& F);

}  // namespace harness
