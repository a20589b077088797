// The states a run leaves for comparison (`harness run --compare DIR`, `harness reference`):
//   DIR/surfaces.csv    the surface vertices of every body after the last step:
//                       body,node,x,y,z,x0,y0,z0,signed_distance (node body-local; x0..z0 its rest
//                       position; the signed distance to the body's contact partner, m, negative
//                       inside; empty when not measured)
//   DIR/trajectory.bin  with output.trajectory: the surface vertices at every measured step and
//                       the last one (little-endian: "HTRJ" 1, body count, per body its name
//                       length, name and surface vertex count; then records of the step (int32),
//                       the time (float64) and every body's x, y, z, signed distance (float64,
//                       NaN when not measured)).
#pragma once

#include "core/world.hpp"

#include <cstdio>
#include <string>
#include <vector>

namespace harness {

// Surface vertices of the bodies of one state.
struct SurfaceState {
  int step = 0;
  double time = 0.0;
  std::vector<std::string> bodies;
  std::vector<Points> x;                  // per body, per surface vertex
  std::vector<Points> x0;                 // the same at rest (surfaces.csv only)
  std::vector<std::vector<double>> sd;    // per body, per surface vertex (NaN: not measured)

  int body(const std::string& name) const;  // index, -1 when absent
};

// The world's surface vertices, with the signed distances given (per body; an empty vector or a
// missing body: not measured).
SurfaceState surface_state(const World& w, int step, double time, const std::vector<std::vector<double>>& sd);

void write_surfaces(const std::string& path, const SurfaceState& s);
// Throws InputError(path, ...) on a missing or malformed file.
SurfaceState read_surfaces(const std::string& path);

class TrajectoryWriter {
 public:
  TrajectoryWriter(const std::string& path, const World& w);
  ~TrajectoryWriter();
  TrajectoryWriter(const TrajectoryWriter&) = delete;
  TrajectoryWriter& operator=(const TrajectoryWriter&) = delete;
  void record(const SurfaceState& s);
  void close();

 private:
  std::string path_;
  std::FILE* f_ = nullptr;
};

// All records of a trajectory file; throws InputError(path, ...) when it is malformed.
std::vector<SurfaceState> read_trajectory(const std::string& path);

}  // namespace harness
