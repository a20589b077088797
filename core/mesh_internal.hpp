// What the surface check (mesh_check.cpp) and the OFF / OBJ reader (mesh_read.cpp) share: how a
// surface's vertices and faces are named in messages, and the check itself with those names.
#pragma once

#include "core/mesh.hpp"

#include <string>
#include <vector>

namespace harness::mesh_detail {

// How vertices and faces are named in messages: check_surface uses mesh indices, the reader
// the file's own vertex numbering and the line each face came from.
struct Labels {
  const std::vector<long long>* vertex = nullptr;
  const std::vector<int>* face_line = nullptr;
};

// Every check of check_surface (mesh.hpp), the problem named with `lab`.
SurfaceReport analyze(const Points& V, const std::vector<Tri>& F, const Labels& lab);

}  // namespace harness::mesh_detail
