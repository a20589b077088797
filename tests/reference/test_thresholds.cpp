// CI accuracy thresholds (results/thresholds.json, made by scripts/thresholds.py from measured
// values with stated margins): the paper's voxel model, with the default the ablation chose for
// each bundled scenario, must stay within them against the scenario's committed reference
// solution (results/references/), both ways (position error and gap as well as depth and
// recall); and every threshold set must fail when the method is broken: no force (penetration),
// a voxel four times larger (pushes across a gap), and pushes the wrong way.
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

const fs::path kSource(HARNESS_SOURCE_DIR);

// The thresholds file; a file that lists no scene fails (a threshold test must not pass on an
// empty list), and so does a bundled scenario without thresholds.
json thresholds() {
  std::ifstream in(kSource / "results" / "thresholds.json");
  REQUIRE(in.good());
  json t = json::parse(in);
  REQUIRE(t.contains("scenes"));
  REQUIRE(t["scenes"].is_object());
  REQUIRE(!t["scenes"].empty());
  // Every bundled scenario has thresholds, or is listed under "without" with the reason.
  for (const auto& e : fs::directory_iterator(kSource / "experiments" / "scenes"))
    if (e.path().extension() == ".json") {
      const std::string name = e.path().stem().string();
      INFO("bundled scenario without thresholds and without a stated reason: " << name);
      const bool reasoned = t.contains("without") && t["without"].contains(name) &&
                            t["without"][name].is_string() && !t["without"][name].get<std::string>().empty();
      CHECK((t["scenes"].contains(name) || reasoned));
    }
  return t;
}

struct Figures {
  double pos_err_max, gap_max, depth_max, recall;
};

// Runs a bundled scene with the threshold's method (and `extra` on top) through the same path
// as `harness run --compare`, and reads its summary.
Figures run(const std::string& scene, const json& t, const json& method, std::vector<std::pair<std::string, std::string>> extra) {
  std::vector<std::pair<std::string, std::string>> ov = {
      {"output.frames_every", "0"},
      {"references.solvers", R"(["cgal"])"},
      {"references.every", std::to_string(t["every"].get<int>())},
      {"time.settle.max_steps", std::to_string(t["settle_max_steps"].get<int>())}};
  for (const auto& [k, v] : method.items()) ov.emplace_back(k, v.get<std::string>());
  ov.insert(ov.end(), extra.begin(), extra.end());
  const Scene sc = load_scene((kSource / "experiments" / "scenes" / (scene + ".json")).string(), ov);
  const fs::path dir = fs::temp_directory_path() / ("harness_thresholds_" + std::to_string(::getpid()) + "_" + scene);
  RunOptions opt;
  opt.out_dir = dir.string();
  opt.measurer = make_reference_measurer;
  opt.exact_detectors = make_exact_detector;
  opt.compare_dir = (kSource / "results" / "references" / scene).string();
  const int code = run_scene(sc, opt);
  Figures f{1e9, 1e9, 1e9, 0.0};  // a run that diverged fails every threshold
  if (code == 0) {
    std::ifstream in(dir / "summary.json");
    const json s = json::parse(in);
    const json& p = s["pairs"][0];
    const json& e = p["error_vs_reference"];
    f = {e["pos_err_max"].get<double>(), e["gap_max"].get<double>(), e["depth_max"].get<double>(),
         p["recall"].get<double>()};
  }
  fs::remove_all(dir);
  return f;
}

int failed(const Figures& f, const json& th) {
  return (f.pos_err_max > th["max_pos_err_max"].get<double>()) + (f.gap_max > th["max_gap_max"].get<double>()) +
         (f.depth_max > th["max_depth_max"].get<double>()) + (f.recall < th["min_recall"].get<double>());
}

}  // namespace

TEST_CASE("CI accuracy thresholds hold on the bundled scenarios", "[thresholds]") {
  const json t = thresholds();
  for (const auto& [scene, th] : t["scenes"].items()) {
    const Figures f = run(scene, t, th["method"], {});
    INFO(scene << ": position error " << f.pos_err_max << " m (max " << th["max_pos_err_max"] << "), gap " << f.gap_max
               << " m (max " << th["max_gap_max"] << "), depth " << f.depth_max << " m (max " << th["max_depth_max"]
               << "), recall " << f.recall << " (min " << th["min_recall"] << ")");
    CHECK(f.pos_err_max <= th["max_pos_err_max"].get<double>());
    CHECK(f.gap_max <= th["max_gap_max"].get<double>());
    CHECK(f.depth_max <= th["max_depth_max"].get<double>());
    CHECK(f.recall >= th["min_recall"].get<double>());
  }
}

TEST_CASE("each CI threshold set fails when the method is broken", "[thresholds][broken]") {
  const json t = thresholds();
  for (const auto& [scene, th] : t["scenes"].items()) {
    const double voxel = std::stod(th["method"]["contacts.0.voxel_size"].get<std::string>());
    const std::pair<const char*, std::vector<std::pair<std::string, std::string>>> twins[] = {
        {"no force", {{"contacts.0.force", "0"}}},
        {"a voxel 4 times larger", {{"contacts.0.voxel_size", std::to_string(4.0 * voxel)}}},
        {"pushes the wrong way", {{"contacts.0.invert_push", "true"}}}};
    for (const auto& [what, extra] : twins) {
      const Figures f = run(scene, t, th["method"], extra);
      INFO(scene << " with " << what << ": position error " << f.pos_err_max << " m, gap " << f.gap_max
                 << " m, depth " << f.depth_max << " m, recall " << f.recall);
      CHECK(failed(f, th) >= 1);
    }
  }
}
