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

// Legacy ASCII VTK POLYDATA of a body's closed outward surface.
void write_vtk(const std::string& path, const World& w, int body, const std::string& title);

// Fixed leading columns of steps.csv (DESIGN.md), then the extra ones.
extern const char* const kStepsColumns;

std::string compiler_version();
std::string eigen_version();

}  // namespace harness
