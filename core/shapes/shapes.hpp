// Generation of mass-spring models from shape descriptions. Every generator returns a
// ShapeModel whose first n_surface nodes are the vertices of a closed, outward-oriented,
// 2-manifold triangle surface; volumetric models add interior nodes after them. Everything here
// runs once at load time: written for clarity and robustness, but O(n log n), so that surfaces of
// millions of vertices remain buildable. The files: primitives.cpp (icosphere, cylinder, mesh),
// box_lattice.cpp, model.cpp (assembly: finish_model), volume_fill.cpp (interior lattice),
// calibration.cpp (springs' stiffness per unit E), kd_tree.hpp, internal.hpp (what they share).
#pragma once

#include "core/limits.hpp"
#include "core/elastic_map.hpp"
#include "core/mesh.hpp"
#include "core/types.hpp"

#include <string>

namespace harness {

enum class Fill { shell, volume };

struct ShapeModel {
  Points nodes;              // rest positions, m
  int n_surface = 0;         // nodes[0..n_surface) are the surface vertices
  std::vector<Tri> faces;    // outward triangles over 0..n_surface-1
  std::vector<Edge> springs; // node index pairs, no duplicates, no self-springs
  // Per spring: its stiffness per unit Young's modulus and role (elastic_map.hpp).
  std::vector<double> spring_kappa;
  std::vector<SpringRole> spring_role;
  // Largest deviation of the lattice's elastic constants from isotropy, in units of the shear
  // modulus (0: isotropic; box cells longer than about 1.2 : 1 cannot be).
  double kappa_anisotropy = 0.0;
  std::vector<double> node_volume;  // lumped volume per node, m^3; sums to the enclosed volume
  std::vector<Cell> cells;          // a box lattice's hexahedral cells (empty for other shapes)
  double volume = 0.0;       // enclosed volume, m^3
};

// Box lattice of (nx+1)(ny+1)(nz+1) nodes: structural, face-shear and body-diagonal springs.
// Always volumetric. Lumped volume: each cell gives 1/8 of its volume to each corner.
// alternating: the surface quads split along alternating diagonals (a checkerboard), else all
// along the same one.
ShapeModel make_box(const Vec3& min, const Vec3& max, const Vec3i& cells, bool alternating = false);

// Limits of the generators, and of the scene format: core/limits.hpp.

// Icosphere: an icosahedron subdivided `subdivisions` times (each splits every triangle in
// four), projected onto the sphere; 10*4^s + 2 surface vertices.
ShapeModel make_sphere(const Vec3& center, double radius, int subdivisions, Fill fill);
// Icosphere scaled by radii (a, b, c) along x, y, z.
ShapeModel make_ellipsoid(const Vec3& center, const Vec3& radii, int subdivisions, Fill fill);
// Cylinder of given axis (normalised internally), radius and length centred at `center`:
// `segments` nodes around, `rings` + 1 circles along the length, caps closed by a fan around
// a centre node each.
ShapeModel make_cylinder(const Vec3& center, const Vec3& axis, double radius, double length,
                         int segments, int rings, Fill fill);
// A closed 2-manifold surface (already validated), scaled then translated.
ShapeModel make_from_surface(const SurfaceMesh& mesh, double scale, const Vec3& translate,
                             Fill fill);

// Shell fill: edge springs plus one bending spring across each edge (joining the two
// vertices opposite it). Volume fill: interior lattice nodes (spacing = mean edge length)
// strictly inside the surface, joined to lattice neighbours and to nearby surface nodes.
// Applied by the generators above; exposed for tests.
ShapeModel finish_model(Points surface_nodes, std::vector<Tri> faces, Fill fill);

}  // namespace harness
