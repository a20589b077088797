// The frames of a run (frames.hpp has the file formats): one file per body and frame under
// DIR/frames, and with the XML formats a ParaView collection per body carrying each frame's
// physical time, rewritten after every frame.
#pragma once

#include "core/run/recorder.hpp"
#include "core/simulation.hpp"

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace harness {

class FrameWriter {
 public:
  FrameWriter(const std::filesystem::path& dir, const Simulation& sim);
  // The frames of step `step` (the state now), when the scene writes frames (output.frames_every).
  void write(const Simulation& sim, const Recorder& rec, int step);

 private:
  std::filesystem::path dir_;
  std::vector<std::vector<std::pair<double, std::string>>> series_;  // per body: (time, file)
};

// Contact force on each node in the last step, N (zero where none acted; NaN on the bodies of a
// pair whose response is projection, which applies no force, or whose contact a peer engine
// handles).
Points contact_forces(const Simulation& sim);

}  // namespace harness
