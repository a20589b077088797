// The command-line program `harness` (DESIGN.md, "Command line").
#include "core/parallel.hpp"
#include "core/run.hpp"
#include "core/scene.hpp"
#include "experiments/bench.hpp"
#include "experiments/sweep.hpp"

#ifdef HARNESS_HAVE_REFERENCE
#include "reference/reference.hpp"
#endif

#include <CLI/CLI.hpp>

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>

namespace fs = std::filesystem;
using namespace harness;

namespace {

// Bundled scenes: $HARNESS_SCENES, else experiments/scenes next to the build, else the source tree.
std::vector<fs::path> scene_roots() {
  std::vector<fs::path> roots;
  if (const char* env = std::getenv("HARNESS_SCENES")) roots.emplace_back(env);
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) roots.push_back(exe.parent_path() / ".." / ".." / "experiments" / "scenes");
  roots.emplace_back(fs::path(HARNESS_SOURCE_DIR) / "experiments" / "scenes");
  return roots;
}

// A path that exists, or the name of a bundled scene ("cylinder_press", "hard/fast_impact").
std::string resolve_scene(const std::string& arg) {
  std::error_code ec;
  if (fs::is_regular_file(arg, ec)) return arg;
  if (arg.find('/') == std::string::npos || arg.rfind("hard/", 0) == 0) {
    for (const fs::path& root : scene_roots()) {
      for (const fs::path& cand : {root / (arg + ".json"), root / "hard" / (arg + ".json")}) {
        if (fs::is_regular_file(cand, ec)) return fs::weakly_canonical(cand).string();
      }
    }
  }
  if (fs::exists(arg, ec)) return arg;  // a directory etc.: read_text_file says what is wrong
  throw InputError(arg, "no such scene file or bundled scene (see `harness list`)");
}

std::vector<std::pair<std::string, std::string>> parse_sets(const std::vector<std::string>& sets) {
  std::vector<std::pair<std::string, std::string>> out;
  for (const std::string& s : sets) {
    const auto eq = s.find('=');
    if (eq == std::string::npos || eq == 0) throw InputError("--set " + s, "expected KEY=JSON");
    out.emplace_back(s.substr(0, eq), s.substr(eq + 1));
  }
  return out;
}

int cmd_list() {
  std::vector<std::pair<std::string, std::string>> rows;
  for (const fs::path& root : scene_roots()) {
    std::error_code ec;
    if (!fs::is_directory(root, ec)) continue;
    for (const fs::path& sub : {root, root / "hard"}) {
      if (!fs::is_directory(sub, ec)) continue;
      for (const auto& e : fs::directory_iterator(sub)) {
        if (e.path().extension() != ".json") continue;
        const std::string name = (sub == root ? "" : "hard/") + e.path().stem().string();
        std::string desc;
        try {
          const Scene s = load_scene(e.path().string());
          desc = s.name + ": " + std::to_string(s.bodies.size()) + " bodies, " +
                 std::to_string(s.contacts.size()) + " contacts, " + std::to_string(s.steps) + " steps";
        } catch (const std::exception& ex) {
          desc = std::string("(invalid: ") + ex.what() + ")";
        }
        rows.emplace_back(name, desc);
      }
    }
    break;  // the first root that exists
  }
  std::sort(rows.begin(), rows.end());
  for (const auto& [n, d] : rows) std::printf("%-32s %s\n", n.c_str(), d.c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"harness: soft bodies as nonlinear mass-spring models, collisions by the local voxel "
               "model of Nikolaev (2013), measured against FCL and CGAL"};
  app.require_subcommand(1);

  std::string scene_arg, out_dir = "out";
  std::vector<std::string> sets;
  int steps = -1;
  bool quiet = false;
  CLI::App* run = app.add_subcommand("run", "simulate a scene and write steps.csv, summary.json, frames/");
  run->add_option("SCENE", scene_arg, "scene file, or the name of a bundled scene")->required();
  run->add_option("--out", out_dir, "output folder")->capture_default_str();
  run->add_option("--set", sets, "override a scene value: KEY=JSON (dotted key, list indices)");
  run->add_option("--steps", steps, "run exactly N steps: override time.steps and turn time.settle off");
  run->add_flag("--quiet", quiet, "no progress line");
  int run_threads = 0;
  run->add_option("--threads", run_threads, "threads of the parallel kernels (default $HARNESS_THREADS or 1); results do not depend on it");

  app.add_subcommand("list", "list the bundled scenes");

  SweepOptions sw;
  std::string sweep_scene;
  CLI::App* sweep = app.add_subcommand("sweep", "run the Cartesian product of --grid values, one run folder per point, merged into DIR/runs.csv");
  sweep->add_option("SCENE", sweep_scene, "scene file, or the name of a bundled scene")->required();
  sweep->add_option("--grid", sw.grids, "KEY=V1,V2,... (JSON values; bare words are strings)")->required();
  sweep->add_option("--set", sw.sets, "a fixed override for every point: KEY=JSON");
  sweep->add_option("--out", sw.out_dir, "output folder")->required();
  sweep->add_option("-j", sw.jobs, "points run at once")->capture_default_str();
  sweep->add_flag("--list", sw.list, "print one `harness run` command per point and exit");
  sweep->add_option("--index", sw.index, "run only point I (0-based), then merge runs.csv");
  sweep->add_flag("--merge", sw.merge, "run nothing; rewrite DIR/runs.csv from the points already complete");

  BenchOptions bo;
  CLI::App* bench = app.add_subcommand("bench", "time detection, references, steps and bandwidth limits on generated scenes; one CSV");
  bench->add_flag("--quick", bo.quick, "stop at 10^5 nodes per body");
  bench->add_option("--out", bo.out, "CSV file")->required();
  bench->add_option("--sizes", bo.sizes, "nodes per body (default 1000,10000,100000[,1000000])")->delimiter(',');
  bench->add_option("--threads", bo.threads, "thread counts to time")->delimiter(',')->capture_default_str();
  bench->add_option("--min-time", bo.min_seconds, "seconds of repetitions per row (at least 3 reps)")->capture_default_str();
  bench->add_flag("!--no-references", bo.references, "skip the fcl and cgal rows");
  bench->add_option("--methods", bo.methods, "only these rows (CSV method names; default all)")->delimiter(',');

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "harness: error: %s (see harness --help)\n", e.what());
    return 2;
  }

  try {
    if (app.got_subcommand("list")) return cmd_list();
    if (app.got_subcommand("bench")) {
      for (long long n : bo.sizes)
        if (n < 8) throw InputError("--sizes", "nodes per body must be >= 8");
      if (bo.threads.empty()) throw InputError("--threads", "needs at least one thread count");
      for (int t : bo.threads)
        if (t < 1) throw InputError("--threads", "must be >= 1");
      if (!(bo.min_seconds >= 0.0)) throw InputError("--min-time", "must be >= 0");
      for (const std::string& m : bo.methods)
        if (std::find(bench_methods().begin(), bench_methods().end(), m) == bench_methods().end())
          throw InputError("--methods", "unknown method '" + m + "'");
      return run_bench(bo);
    }
    if (app.got_subcommand("sweep")) {
      sw.scene = resolve_scene(sweep_scene);
      sw.scene_arg = sweep_scene;
      std::error_code ec;
      sw.self = fs::read_symlink("/proc/self/exe", ec).string();
      if (ec) sw.self = argv[0];
      if (sw.jobs < 1) throw InputError("-j", "must be >= 1");
      if (sweep->count("--index") && sw.index < 0) throw InputError("--index", "must be >= 0");
      return run_sweep(sw);
    }
    if (run->count("--threads")) {
      if (run_threads < 1) throw InputError("--threads", "must be >= 1");
      set_threads(run_threads);
    }
    const std::string path = resolve_scene(scene_arg);
    auto overrides = parse_sets(sets);
    if (steps >= 0) {
      overrides.emplace_back("time.steps", std::to_string(steps));
      overrides.emplace_back("time.settle", "null");
    }
    else if (run->count("--steps")) throw InputError("--steps", "must be >= 0");
    const Scene scene = load_scene(path, overrides);
    RunOptions opt;
    opt.out_dir = out_dir;
    opt.progress = !quiet;
#ifdef HARNESS_HAVE_REFERENCE
    opt.measurer = make_reference_measurer;
    opt.exact_detectors = make_exact_detector;
    opt.versions = reference_version_map();
#endif
    return run_scene(scene, opt);
  } catch (const InputError& e) {
    std::fprintf(stderr, "harness: error: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "harness: error: %s\n", e.what());
    return 1;
  }
}
