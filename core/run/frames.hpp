// Frames of a run: each body's closed, outward surface at step 0, every output.frames_every
// steps and at the last step, as DIR/frames/<body>_<step, 6 digits>.vtk.
#pragma once

#include "core/world.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace harness {

// Legacy ASCII VTK POLYDATA of a body's closed outward surface; with `penetrating` (per body
// node, body-local) also POINT_DATA "penetrating" (0/1) on the surface vertices.
void write_vtk(const std::string& path, const World& w, int body, const std::string& title,
               const std::vector<std::uint8_t>* penetrating = nullptr);

}  // namespace harness
