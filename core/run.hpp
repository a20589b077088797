// `harness run`: simulates a scene and writes DIR/steps.csv, DIR/summary.json and
// DIR/frames/*.vtk (DESIGN.md, "Outputs of harness run").
#pragma once

#include "core/measure.hpp"
#include "core/scene.hpp"
#include "core/simulation.hpp"

#include <map>
#include <string>

namespace harness {

struct RunOptions {
  std::string out_dir = "out";
  bool progress = false;  // a progress line on stderr
  MeasurerFactory measurer;  // empty: references unavailable in this build
  std::map<std::string, std::string> versions;  // extra library versions (FCL, CGAL)
};

// Exit status: 0 done, 3 the state became non-finite (last good state and summary written).
// Throws InputError before anything is written when the scene cannot be built.
int run_scene(const Scene& scene, const RunOptions& options);

// Legacy ASCII VTK POLYDATA of a body's closed outward surface; with `penetrating` (per body
// node, body-local) also POINT_DATA "penetrating" (0/1) on the surface vertices.
void write_vtk(const std::string& path, const World& w, int body, const std::string& title,
               const std::vector<std::uint8_t>* penetrating = nullptr);

// Unit vector from the host's to the guest's bounding-box centre (the approach side).
Vec3 approach_axis(const World& w, const ContactSpec& pair);
// Guest nodes that lie beyond the host's far side along `axis` (the approach axis at rest):
// nodes that tunnelled through the host. summary.json: pairs[].tunnelled.
int tunnelled_nodes(const World& w, const ContactSpec& pair, const Vec3& axis);

// Fixed leading columns of steps.csv (DESIGN.md), then the extra ones.
extern const char* const kStepsColumns;

std::string compiler_version();
std::string eigen_version();

}  // namespace harness
