#include "core/run/output_dir.hpp"

#include "core/types.hpp"

#include <cstdio>
#include <string>
#include <system_error>

namespace harness {

namespace fs = std::filesystem;

void prepare_output(const fs::path& dir, bool frames) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec || !fs::is_directory(dir)) throw InputError("--out " + dir.string(), "cannot create the output folder" + (ec ? " (" + ec.message() + ")" : std::string()));
  {
    const fs::path probe = dir / ".harness_write_test";
    std::FILE* f = std::fopen(probe.c_str(), "w");
    if (!f) throw InputError("--out " + dir.string(), "the output folder is not writable");
    std::fclose(f);
    fs::remove(probe, ec);
  }
  fs::remove(dir / "summary.json");
  const fs::path fr = dir / "frames";
  if (fs::exists(fr))
    for (const auto& e : fs::directory_iterator(fr))
      if (e.path().extension() == ".vtk" || e.path().extension() == ".vtp" || e.path().extension() == ".vtu" ||
          e.path().extension() == ".pvd")
        fs::remove(e.path());
  if (frames) fs::create_directories(fr);
}

}  // namespace harness
