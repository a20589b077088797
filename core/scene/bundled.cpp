#include "core/scene/bundled.hpp"

#include "core/types.hpp"

#include <cstdlib>

namespace harness {

namespace fs = std::filesystem;

std::vector<fs::path> scene_roots() {
  std::vector<fs::path> roots;
  if (const char* env = std::getenv("HARNESS_SCENES")) roots.emplace_back(env);
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) roots.push_back(exe.parent_path() / ".." / ".." / "experiments" / "scenes");
  roots.emplace_back(fs::path(HARNESS_SOURCE_DIR) / "experiments" / "scenes");
  return roots;
}

std::string resolve_scene(const std::string& arg) {
  std::error_code ec;
  if (fs::is_regular_file(arg, ec)) return arg;
  if (arg.find('/') == std::string::npos || arg.rfind("hard/", 0) == 0 || arg.rfind("bullet/", 0) == 0) {
    for (const fs::path& root : scene_roots()) {
      for (const fs::path& cand : {root / (arg + ".json"), root / "hard" / (arg + ".json")}) {
        if (fs::is_regular_file(cand, ec)) return fs::weakly_canonical(cand).string();
      }
    }
  }
  if (fs::exists(arg, ec)) return arg;  // a directory etc.: read_text_file says what is wrong
  throw InputError(arg, "no such scene file or bundled scene (see `harness list`)");
}

}  // namespace harness
