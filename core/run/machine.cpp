#include "core/run/machine.hpp"

#include <fstream>
#include <thread>

namespace harness {

nlohmann::json machine_info() {
  std::string model = "unknown";
  std::ifstream in("/proc/cpuinfo");
  for (std::string line; std::getline(in, line);)
    if (line.rfind("model name", 0) == 0) {
      const auto c = line.find(':');
      if (c != std::string::npos && c + 2 <= line.size()) model = line.substr(c + 2);
      break;
    }
  return {{"cpu", model}, {"cores", std::thread::hardware_concurrency()}};
}

std::string machine_string() {
  const nlohmann::json m = machine_info();
  return m["cpu"].get<std::string>() + " (" + std::to_string(m["cores"].get<unsigned>()) + " cores)";
}

}  // namespace harness
