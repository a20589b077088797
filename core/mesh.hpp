// Triangle surface meshes: reading OFF and OBJ, and checking that a surface is closed,
// 2-manifold and outward oriented. V is #V x 3 positions (m), F is #F x 3 vertex indices.
#pragma once

#include "core/types.hpp"

#include <string>

namespace harness {

struct SurfaceMesh {
  Points V;
  std::vector<Tri> F;
};

struct SurfaceReport {
  bool closed = false;         // every undirected edge is shared by exactly two faces
  bool manifold = false;       // and each vertex's faces form a single fan (one cycle)
  bool oriented = false;       // the two faces of every edge traverse it in opposite directions
  int euler = 0;               // V - E + F
  int components = 0;          // connected components
  double signed_volume = 0.0;  // > 0 for outward orientation, m^3
  std::string problem;         // first problem found, empty if none
  bool ok() const { return closed && manifold && oriented && signed_volume > 0.0; }
};

// Topological and orientation checks of a triangle surface (vertices unreferenced by F are
// a problem too).
SurfaceReport check_surface(const SurfaceMesh& mesh);
double signed_volume(const Points& V, const std::vector<Tri>& F);

// Read an OFF or OBJ file (by extension, case-insensitive). Polygons are fan-triangulated.
// Throws InputError with "path:line:col" (or "path") on: missing or unreadable file, bad
// syntax, non-finite numbers, absurd counts, indices out of range, degenerate faces, a
// surface that is not closed, not 2-manifold or not consistently oriented. An inward-oriented
// surface (negative volume) is flipped. Vertices referenced by no face are dropped.
SurfaceMesh read_surface(const std::string& path);
// The same reader on text already in memory (what read_surface does after reading the file):
// `name` stands for the path in messages, `obj` picks OBJ over OFF. Used by the fuzz targets.
SurfaceMesh read_surface_text(const std::string& text, const std::string& name, bool obj);

}  // namespace harness
