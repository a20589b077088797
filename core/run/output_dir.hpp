// The output folder of a run (--out DIR).
#pragma once

#include <filesystem>

namespace harness {

// Makes DIR (and DIR/frames when frames are written) and checks it can be written. A previous
// run's summary is removed first, so that an interrupted run never looks complete; its frames
// are removed too, so the series is this run's only. A folder that cannot be made or written is
// bad input (InputError, exit 2), found before anything is written.
void prepare_output(const std::filesystem::path& dir, bool frames);

}  // namespace harness
