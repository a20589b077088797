// Parameters of one contact pair as resolved from the scene (DESIGN.md, "Contact pair").
#pragma once

#include <string>

namespace harness {

enum class Region { half, full, overlap };
enum class HostNodes { all, surface };
enum class EliminatorKind { line, plane };

struct ContactSpec {
  int host = -1;                 // body index in World::bodies
  int guest = -1;
  std::string detector = "voxel";  // "voxel" | "cgal" | "fcl" (the latter two from reference/)
  double voxel_size = 0.0;       // requested, m; rounded down to a power of two; 0 = automatic
  Region region = Region::half;
  int margin = 1;                // voxels added around the region
  HostNodes host_nodes = HostNodes::all;
  EliminatorKind eliminator = EliminatorKind::line;
  bool force_auto = false;
  double force = 1.0;            // N per contact when !force_auto
};

}  // namespace harness
