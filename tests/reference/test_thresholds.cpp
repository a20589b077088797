// CI accuracy thresholds (results/thresholds.json, made by scripts/thresholds.py from measured
// window figures with stated margins): per bundled scenario, the paper's voxel model with the
// default the ablation chose (where it chose one) and the completed model (voxel_exact, both ways,
// the penalty) must stay within them against the scenario's committed reference solution
// (results/references/): position error and gap (window means), depth and tunnelled nodes
// (window maxima), recall; and every threshold set must fail when its method is broken: no force
// (penetration) and pushes the wrong way.
#include "core/run/run_scene.hpp"
#include "reference/reference.hpp"

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>

#include <unistd.h>

using namespace harness;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

const fs::path kSource(HARNESS_SOURCE_DIR);

// The thresholds file; a file that lists no check fails (a threshold test must not pass on an
// empty list), and so does a bundled scenario without a check of the completed model, or without
// one of the paper's model and without a stated reason.
json thresholds() {
  std::ifstream in(kSource / "results" / "thresholds.json");
  REQUIRE(in.good());
  json t = json::parse(in);
  REQUIRE(t.contains("checks"));
  REQUIRE(t["checks"].is_array());
  REQUIRE(!t["checks"].empty());
  for (const auto& e : fs::directory_iterator(kSource / "experiments" / "scenes"))
    if (e.path().extension() == ".json") {
      const std::string name = e.path().stem().string();
      bool paper = false, completed = false;
      for (const json& c : t["checks"]) {
        if (c["scene"] != name) continue;
        paper = paper || c["method"] == "paper";
        completed = completed || c["method"] == "completed";
      }
      const bool reasoned = t.contains("without") && t["without"].contains(name) && t["without"][name].is_string() &&
                            !t["without"][name].get<std::string>().empty();
      INFO("bundled scenario " << name << ": a check of the completed model, and of the paper's model or a reason");
      CHECK(completed);
      CHECK((paper || reasoned));
    }
  return t;
}

struct Figures {
  double pos_err_max, gap_max, depth_max, tunnelled, recall;
};

double window_stat(const json& ew, const char* figure, const char* what) {
  const json& f = ew[figure];
  return f.is_object() && f[what].is_number() ? f[what].get<double>() : 1e9;  // not measured: fails
}

// Runs a bundled scene with the check's method (and `extra` on top) through the same path as
// `harness run --compare`, and reads its window figures.
Figures run(const json& t, const json& check, std::vector<std::pair<std::string, std::string>> extra) {
  const std::string scene = check["scene"].get<std::string>();
  std::vector<std::pair<std::string, std::string>> ov = {
      {"output.frames_every", "0"},
      {"references.solvers", R"(["cgal"])"},
      {"references.every", std::to_string(t["every"].get<int>())},
      {"time.settle.max_steps", std::to_string(t["settle_max_steps"].get<int>())}};
  for (const auto& [k, v] : check["sets"].items()) ov.emplace_back(k, v.get<std::string>());
  ov.insert(ov.end(), extra.begin(), extra.end());
  const Scene sc = load_scene((kSource / "experiments" / "scenes" / (scene + ".json")).string(), ov);
  const fs::path dir = fs::temp_directory_path() /
                       ("harness_thresholds_" + std::to_string(::getpid()) + "_" + scene + "_" + check["method"].get<std::string>());
  RunOptions opt;
  opt.out_dir = dir.string();
  opt.measurer = make_reference_measurer;
  opt.exact_detectors = make_exact_detector;
  opt.compare_dir = (kSource / "results" / "references" / scene).string();
  const int code = run_scene(sc, opt);
  Figures f{1e9, 1e9, 1e9, 1e9, 0.0};  // a run that diverged fails every threshold
  if (code == 0) {
    std::ifstream in(dir / "summary.json");
    const json s = json::parse(in);
    const json& p = s["pairs"][0];
    const json& ew = p["error_vs_reference"]["window"];
    f = {window_stat(ew, "pos_err_max", "mean"), window_stat(ew, "gap_max", "mean"), window_stat(ew, "depth_max", "max"),
         window_stat(ew, "tunnelled", "max"), p["recall"].is_number() ? p["recall"].get<double>() : 0.0};
  }
  fs::remove_all(dir);
  return f;
}

int failed(const Figures& f, const json& th) {
  return (f.pos_err_max > th["max_pos_err_max"].get<double>()) + (f.gap_max > th["max_gap_max"].get<double>()) +
         (f.depth_max > th["max_depth_max"].get<double>()) + (f.tunnelled > th["max_tunnelled"].get<double>()) +
         (f.recall < th["min_recall"].get<double>());
}

std::string describe(const Figures& f) {
  std::ostringstream o;
  o << "position error " << f.pos_err_max << " m, gap " << f.gap_max << " m, depth " << f.depth_max << " m, tunnelled "
    << f.tunnelled << ", recall " << f.recall;
  return o.str();
}

}  // namespace

TEST_CASE("CI accuracy thresholds hold on the bundled scenarios", "[thresholds]") {
  const json t = thresholds();
  for (const json& c : t["checks"]) {
    const Figures f = run(t, c, {});
    INFO(c["scene"].get<std::string>() << ", " << c["label"].get<std::string>() << ": " << describe(f) << "; thresholds "
                                        << c["max_pos_err_max"] << ", " << c["max_gap_max"] << ", " << c["max_depth_max"]
                                        << ", " << c["max_tunnelled"] << ", " << c["min_recall"]);
    CHECK(f.pos_err_max <= c["max_pos_err_max"].get<double>());
    CHECK(f.gap_max <= c["max_gap_max"].get<double>());
    CHECK(f.depth_max <= c["max_depth_max"].get<double>());
    CHECK(f.tunnelled <= c["max_tunnelled"].get<double>());
    CHECK(f.recall >= c["min_recall"].get<double>());
  }
}

TEST_CASE("each CI threshold set fails when its method is broken", "[thresholds][broken]") {
  const json t = thresholds();
  for (const json& c : t["checks"]) {
    // (A voxel four times larger is not a broken method: with the cylinder's default, the depth
    // penalty at 16 mm, 64 mm voxels end 4.47 mm from the reference against 4.78 mm; measured
    // 2026-11-25. It is not a twin.)
    const std::vector<std::pair<const char*, std::vector<std::pair<std::string, std::string>>>> twins = {
        {"no force", {{"contacts.0.force", "0"}}}, {"pushes the wrong way", {{"contacts.0.invert_push", "true"}}}};
    for (const auto& [what, extra] : twins) {
      const Figures f = run(t, c, extra);
      INFO(c["scene"].get<std::string>() << ", " << c["label"].get<std::string>() << ", with " << what << ": "
                                          << describe(f));
      CHECK(failed(f, c) >= 1);
    }
  }
}
