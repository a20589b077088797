// Frames of a run: each body's closed, outward surface at step 0, every output.frames_every
// steps and at the last step, as DIR/frames/<body>_<step, 6 digits>.<vtp|vtu|vtk>
// (output.format), with a ParaView collection DIR/frames/<body>.pvd that gives every XML frame
// its physical time (rewritten after each frame: an interrupted run's series is still valid).
#pragma once

#include "core/scene/scene.hpp"
#include "core/world.hpp"

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace harness {

// Point data of one body's surface vertices in one frame. Every XML frame carries the same
// arrays; a quantity not measured at that step is NaN (never a missing array).
struct FrameData {
  std::vector<Vec3> contact_force;              // N, per surface vertex (empty: NaN)
  const std::vector<double>* signed_distance = nullptr;  // m, negative inside (null: NaN)
  const std::vector<std::uint8_t>* penetrating = nullptr;  // per body node (null: NaN)
};

// Legacy ASCII VTK POLYDATA of a body's closed outward surface; with `penetrating` (per body
// node, body-local) also POINT_DATA "penetrating" (0/1) on the surface vertices.
void write_vtk(const std::string& path, const World& w, int body, const std::string& title,
               const std::vector<std::uint8_t>* penetrating = nullptr);

// VTK XML (PolyData, or UnstructuredGrid of triangles with `unstructured`) of a body's surface,
// base64 binary, with the point arrays displacement (from the rest positions, m), velocity (m/s),
// contact_force (N), signed_distance (m) and penetrating (0/1).
void write_vtk_xml(const std::string& path, const World& w, int body, const FrameData& data, bool unstructured);

// A ParaView collection (.pvd): (time, file relative to the collection) per frame.
void write_pvd(const std::string& path, const std::vector<std::pair<double, std::string>>& frames);

}  // namespace harness
