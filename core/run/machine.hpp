// The machine a run or a bench ran on, read from the system (not typed): the processor's model
// (/proc/cpuinfo "model name"; "unknown" where there is none) and its hardware threads.
#pragma once

#include <nlohmann/json.hpp>

#include <string>

namespace harness {

// {"cpu": model, "cores": hardware threads}.
nlohmann::json machine_info();
// The same as one string: "MODEL (N cores)".
std::string machine_string();

}  // namespace harness
