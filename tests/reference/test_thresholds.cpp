// CI accuracy thresholds (results/thresholds.json, made by scripts/thresholds.py from measured
// values with stated margins): the bundled scenarios must meet them, and each threshold must
// fail when the method is broken, so that none is vacuous.
#include "core/run.hpp"
#include "reference/reference.hpp"

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>

#include <unistd.h>

using namespace harness;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

// The thresholds file; a file that lists no scene fails (a threshold test must not pass on an
// empty list), and so does a bundled scenario without thresholds.
json thresholds() {
  std::ifstream in(fs::path(HARNESS_SOURCE_DIR) / "results" / "thresholds.json");
  REQUIRE(in.good());
  json t = json::parse(in);
  REQUIRE(t.contains("scenes"));
  REQUIRE(t["scenes"].is_object());
  REQUIRE(!t["scenes"].empty());
  for (const auto& e : fs::directory_iterator(fs::path(HARNESS_SOURCE_DIR) / "experiments" / "scenes"))
    if (e.path().extension() == ".json") {
      INFO("bundled scenario without thresholds: " << e.path().stem().string());
      CHECK(t["scenes"].contains(e.path().stem().string()));
    }
  return t;
}

struct Figures {
  double recall, depth_voxels;
  int true_pen_final;
};

// Runs a bundled scene through the same path as `harness run` and reads its summary.
Figures run(const std::string& scene, int steps, int every, std::vector<std::pair<std::string, std::string>> extra) {
  std::vector<std::pair<std::string, std::string>> ov = {
      {"time.steps", std::to_string(steps)}, {"output.frames_every", "0"},
      {"references.solvers", R"(["cgal"])"}, {"references.every", std::to_string(every)}};
  ov.insert(ov.end(), extra.begin(), extra.end());
  const Scene sc = load_scene((fs::path(HARNESS_SOURCE_DIR) / "experiments" / "scenes" / (scene + ".json")).string(), ov);
  const fs::path dir = fs::temp_directory_path() / ("harness_thresholds_" + std::to_string(::getpid()) + "_" + scene);
  RunOptions opt;
  opt.out_dir = dir.string();
  opt.measurer = make_reference_measurer;
  opt.exact_detectors = make_exact_detector;
  REQUIRE(run_scene(sc, opt) == 0);
  std::ifstream in(dir / "summary.json");
  const json s = json::parse(in);
  fs::remove_all(dir);
  const json& p = s["pairs"][0];
  Figures f;
  f.recall = p["recall"].get<double>();
  f.true_pen_final = p["true_pen_final"].get<int>();
  f.depth_voxels = p["max_depth_peak"].get<double>() / p["voxel_size_used"].get<double>();
  return f;
}

}  // namespace

TEST_CASE("CI accuracy thresholds hold on the bundled scenarios", "[thresholds]") {
  const json t = thresholds();
  for (const auto& [scene, th] : t["scenes"].items()) {
    const Figures f = run(scene, th["steps"], t["every"], {});
    INFO(scene << ": recall " << f.recall << " (min " << th["min_recall"] << "), true_pen_final " << f.true_pen_final
               << " (max " << th["max_true_pen_final"] << "), depth " << f.depth_voxels << " voxels (max "
               << th["max_depth_voxels"] << ")");
    CHECK(f.recall >= th["min_recall"].get<double>());
    CHECK(f.true_pen_final <= th["max_true_pen_final"].get<int>());
    CHECK(f.depth_voxels <= th["max_depth_voxels"].get<double>());
  }
}

TEST_CASE("each CI threshold fails when the method is broken", "[thresholds][broken]") {
  // Broken elimination: force 0 N. It must violate the penetration and depth thresholds of
  // every scenario. Recall is a property of detection: with no force the guest sinks deeper
  // and detection may even improve (cylinder_press: recall 1.0), so a recall threshold that
  // force 0 leaves intact must fail with broken detection instead: voxels of 0.5 mm, ten
  // times below the node spacing, leave holes in the grid.
  const json t = thresholds();
  for (const auto& [scene, th] : t["scenes"].items()) {
    const Figures f = run(scene, th["steps"], t["every"], {{"contacts.0.force", "0"}});
    INFO(scene << " with force 0: recall " << f.recall << ", true_pen_final " << f.true_pen_final << ", depth "
               << f.depth_voxels << " voxels");
    CHECK(f.true_pen_final > th["max_true_pen_final"].get<int>());
    CHECK(f.depth_voxels > th["max_depth_voxels"].get<double>());
    if (f.recall >= th["min_recall"].get<double>()) {
      const Figures g = run(scene, th["steps"], t["every"], {{"contacts.0.voxel_size", "0.0005"}});
      INFO(scene << " with 0.5 mm voxels: recall " << g.recall);
      CHECK(g.recall < th["min_recall"].get<double>());
    }
  }
}
