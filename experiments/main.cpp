// The command-line program `harness` (docs/usage.md).
#include "core/collision/detectors/collision_detector.hpp"
#include "core/collision/responses/collision_eliminator.hpp"
#include "core/collision/responses/force_rule.hpp"
#include "core/parallel.hpp"
#include "core/run/columns.hpp"
#include "core/run/run_scene.hpp"
#include "core/scene/bundled.hpp"
#include "core/scene/scene.hpp"
#include "experiments/bench.hpp"
#include "experiments/detection.hpp"
#include "experiments/device_run.hpp"
#include "experiments/reference.hpp"
#include "experiments/sweep.hpp"
#include "core/scene/schema.hpp"

#ifdef HARNESS_HAVE_REFERENCE
#include "reference/reference.hpp"
#endif

#include <CLI/CLI.hpp>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>

namespace fs = std::filesystem;
using namespace harness;

namespace {

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
    for (const fs::path& sub : {root, root / "hard", root / "bullet"}) {
      if (!fs::is_directory(sub, ec)) continue;
      for (const auto& e : fs::directory_iterator(sub)) {
        if (e.path().extension() != ".json") continue;
        const std::string name = (sub == root ? "" : sub.filename().string() + "/") + e.path().stem().string();
        std::string desc;
        try {
          const Scene s = load_scene(e.path().string());
          desc = s.name + ": " + std::to_string(s.bodies.size()) + " bodies, " +
                 std::to_string(s.contacts.size()) + " contacts, " + std::to_string(s.steps) + " steps" +
                 (s.settle.present ? " then settling, up to " + std::to_string(s.settle.max_steps) + " more" : "");
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

// The options every program that runs a scene passes: the reference library where linked.
RunOptions run_options() {
#ifdef HARNESS_HAVE_REFERENCE
  return with_references();
#else
  return {};
#endif
}

// The scene as the command line edits it, validated once: the file's document, --set overrides
// in order, --steps (exactly N steps: time.settle off), then --dt-divide N or --dt S (every step
// count scaled: the same physical time).
Scene edited_scene(const std::string& scene, const std::vector<std::string>& sets, bool steps_given, int steps,
                   int dt_divide, bool dt_given, double dt) {
  auto overrides = parse_sets(sets);
  if (steps_given) {
    if (steps < 0) throw InputError("--steps", "must be >= 0");
    for (auto& o : steps_overrides(steps)) overrides.push_back(std::move(o));
  }
  SceneSource src = read_scene_source(resolve_scene(scene));
  for (const auto& [k, v] : overrides) apply_override(src.doc, k, v);
  std::vector<std::string> rounded;
  if (dt_given) rounded = rescale_to_dt(src.doc, dt);
  else rescale_steps(src.doc, dt_divide);
  Scene out = scene_from_source(src);
  out.edit_warnings = std::move(rounded);
  return out;
}

#ifndef HARNESS_HAVE_BULLET
// Without the reference library: --bullet-* parse into this and --engine bullet is refused.
struct BulletOptions {
  double margin = 0.0;
  int iterations = 1;
};
#endif

struct RunCommand {
  CLI::App* cmd = nullptr;
  std::string scene, out = "out";
  std::vector<std::string> sets;
  int steps = -1, threads = 0;
  bool quiet = false, strict = false;
  std::string compare, compare_also;
  int dt_divide = 1;
  double dt = 0.0;
  std::string engine = "harness";
  BulletOptions bullet;
  std::string device;
  bool check_cpu = false;
  std::string node_order = node_order_name(kDefaultNodeOrder);
  int ensemble = 1;
  double max_wall = 0.0;

  void setup(CLI::App& app) {
    cmd = app.add_subcommand("run", "simulate a scene and write steps.csv, summary.json, frames/");
    cmd->add_option("SCENE", scene, "scene file, or the name of a bundled scene")->required();
    cmd->add_option("--out", out, "output folder")->capture_default_str();
    cmd->add_option("--set", sets, "override a scene value: KEY=JSON (dotted key, list indices)");
    cmd->add_option("--steps", steps, "run exactly N steps: override time.steps and turn time.settle off");
    cmd->add_flag("--quiet", quiet, "no progress line");
    cmd->add_flag("--strict", strict, "warnings are errors (exit 2): a rounded voxel size, tunnelling expected or found");
    cmd->add_option("--threads", threads,
                    "threads of the parallel kernels (default $HARNESS_THREADS or 1); results do not depend on it");
    auto* divide =
        cmd->add_option("--dt-divide", dt_divide, "run at dt / N over the same physical time (every step count times N)");
    cmd->add_option("--dt", dt, "run at time step S (s) over the same physical time: every step count times the "
                                "scene's dt / S (exact when that is a whole number, rounded otherwise); --steps counts "
                                "steps of the scene's dt")
        ->excludes(divide);
    cmd->add_option("--compare", compare, "a reference (harness reference) or finished run of the same scene: "
                                          "error_vs_reference in summary.json, pos_err/gap columns");
    cmd->add_option("--compare-also", compare_also, "with --compare: a second reference measured on the same steps "
                                                    "(the other kind: one way against both ways): "
                                                    "error_vs_reference_also in summary.json");
    cmd->add_option("--engine", engine, "harness (its own effects and integrator) or bullet (Bullet's soft bodies, "
                                        "docs/architecture.md)")->capture_default_str();
    cmd->add_option("--bullet-margin", bullet.margin, "with --engine bullet: collision margin of every body, m "
                                                      "(default 0.05 x the body's mean surface edge)");
    cmd->add_option("--bullet-iterations", bullet.iterations, "with --engine bullet: position iterations per step")
        ->capture_default_str();
    cmd->add_option("--device", device, "step on a device: cuda (a GPU) or cpu (the GPU's kernel bodies on one CPU "
                                        "thread); writes summary.json and state.csv (docs/architecture.md)");
    cmd->add_flag("--check-cpu", check_cpu, "with --device: also step the CPU's simulation and record the largest "
                                            "node distance between the two states");
    cmd->add_option("--node-order", node_order, "the nodes' layout in memory: scene (the shape's own numbering), rcm "
                                                "(reverse Cuthill-McKee) or morton; outputs keep the scene's numbering")
        ->capture_default_str();
    cmd->add_option("--max-wall", max_wall, "seconds of wall time after which the run stops as failed (exit 3, "
                                            "outputs written; 0: no limit; harness sweep passes it to every point)")
        ->capture_default_str();
    cmd->add_option("--ensemble", ensemble, "K members differing only in the node order and a jitter far below the "
                                            "mesh's precision (DIR/members/k/); summary.json `ensemble` gives each "
                                            "figure's median and range and the classes (docs/usage.md)")
        ->capture_default_str();
  }
  int exec() {
    NodeOrder order = kDefaultNodeOrder;
    if (!parse_node_order(node_order, order)) throw InputError("--node-order " + node_order, "expected scene, rcm or morton");
    if (!device.empty()) {
      if (engine != "harness" || !compare.empty() || !compare_also.empty())
        throw InputError("--device", "not with --engine or --compare");
      if (order != NodeOrder::scene) throw InputError("--node-order", "not with --device (state.csv is in the scene's order)");
      if (ensemble != 1) throw InputError("--ensemble", "not with --device");
      if (dt_divide < 1) throw InputError("--dt-divide", "must be >= 1");
      const Scene sc = edited_scene(scene, sets, cmd->count("--steps") > 0, steps, dt_divide, cmd->count("--dt") > 0, dt);
      DeviceRunOptions d;
      d.device = device;
      d.out_dir = out;
      d.check_cpu = check_cpu;
      d.progress = !quiet;
      d.exact_detectors = run_options().exact_detectors;
      return run_on_device(sc, d);
    }
    if (check_cpu) throw InputError("--check-cpu", "only with --device");
    if (ensemble < 1 || ensemble > 1000) throw InputError("--ensemble", "expected 1 to 1000 members");
    if (ensemble > 1 && engine != "harness") throw InputError("--ensemble", "not with --engine");
    if (engine != "harness" && engine != "bullet") throw InputError("--engine " + engine, "expected harness or bullet");
    // Bullet's solver visits the springs one after another: another layout is another solver order.
    if (engine == "bullet" && order != NodeOrder::scene) throw InputError("--node-order", "not with --engine bullet");
    if (engine != "bullet" && (cmd->count("--bullet-margin") || cmd->count("--bullet-iterations")))
      throw InputError("--bullet-margin/--bullet-iterations", "only with --engine bullet");
    if (cmd->count("--threads")) {
      if (threads < 1) throw InputError("--threads", "must be >= 1");
      set_threads(threads);
    }
    if (dt_divide < 1) throw InputError("--dt-divide", "must be >= 1");
    const Scene sc = edited_scene(scene, sets, cmd->count("--steps") > 0, steps, dt_divide, cmd->count("--dt") > 0, dt);
    RunOptions opt = run_options();
    opt.out_dir = out;
    opt.progress = !quiet;
    opt.compare_dir = compare;
    opt.compare_also_dir = compare_also;
    opt.strict = strict;
    opt.node_order = order;
    if (engine == "bullet") {
#ifdef HARNESS_HAVE_BULLET
      opt.engine = make_bullet_engine(bullet);
      opt.versions["Bullet"] = bullet_version();
#else
      throw InputError("--engine bullet", "this harness was built without Bullet (libbullet-dev)");
#endif
    }
    opt.ensemble = ensemble;
    if (!(max_wall >= 0.0)) throw InputError("--max-wall", "expected seconds >= 0");
    opt.max_wall_s = max_wall;
    return ensemble > 1 ? run_ensemble(sc, opt) : run_scene(sc, opt);
  }
};

struct ReferenceCommand {
  CLI::App* cmd = nullptr;
  std::string scene;
  std::vector<std::string> sets;
  ReferenceOptions ro;
  bool quiet = false;
  int dt_divide = 1;
  double dt = 0.0;

  void setup(CLI::App& app) {
    cmd = app.add_subcommand("reference", "the converged reference solution of a scene (exact detection, penalty; "
                                          "dt halved and k_c doubled until the settled surfaces agree)");
    cmd->add_option("SCENE", scene, "scene file, or the name of a bundled scene")->required();
    cmd->add_option("--out", ro.out_dir, "output folder")->required();
    cmd->add_option("--set", sets, "override a scene value: KEY=JSON (dotted key, list indices)");
    cmd->add_option("--tolerance", ro.tolerance, "largest change of a surface node between levels, m")->capture_default_str();
    cmd->add_option("--max-levels", ro.max_levels, "levels at most")->capture_default_str();
    cmd->add_option("--min-levels", ro.min_levels, "levels at least (3: an observed order of convergence)")->capture_default_str();
    cmd->add_flag("--one-sided", ro.one_sided, "contact one way only: the guest's nodes kept out of the host (the paper's model)");
    auto* divide =
        cmd->add_option("--dt-divide", dt_divide, "level 0 at dt / N over the same physical time (a finer mesh needs it)");
    cmd->add_option("--dt", dt, "level 0 at time step S (s) over the same physical time (step counts times the "
                                "scene's dt / S, rounded when not whole)")
        ->excludes(divide);
    cmd->add_option("--stiffness", ro.stiffness, "k_c of level 0, N/m (default: the scene's penalty stiffness)");
    cmd->add_flag("--quiet", quiet, "no progress line");
  }
  int exec() {
    if (!(ro.tolerance > 0.0)) throw InputError("--tolerance", "must be > 0");
    if (ro.max_levels < 2) throw InputError("--max-levels", "must be >= 2 (a change needs two levels)");
    if (ro.min_levels < 2 || ro.min_levels > ro.max_levels)
      throw InputError("--min-levels", "must be from 2 to --max-levels");
    if (cmd->count("--stiffness") && !(ro.stiffness > 0.0)) throw InputError("--stiffness", "must be > 0");
    if (dt_divide < 1) throw InputError("--dt-divide", "must be >= 1");
    const Scene sc = edited_scene(scene, sets, false, -1, dt_divide, cmd->count("--dt") > 0, dt);
    ro.run = run_options();
    ro.progress = !quiet;
    return run_reference(sc, ro);
  }
};

struct SweepCommand {
  CLI::App* cmd = nullptr;
  SweepOptions sw;
  std::string scene;

  void setup(CLI::App& app) {
    cmd = app.add_subcommand("sweep", "run the Cartesian product of --grid values, one run folder per point, merged into DIR/runs.csv");
    cmd->add_option("SCENE", scene, "scene file, or the name of a bundled scene")->required();
    cmd->add_option("--grid", sw.grids, "KEY=V1,V2,... (JSON values; bare words are strings)")->required();
    cmd->add_option("--set", sw.sets, "a fixed override for every point: KEY=JSON");
    cmd->add_option("--out", sw.out_dir, "output folder")->required();
    cmd->add_option("-j", sw.jobs, "points run at once")->capture_default_str();
    cmd->add_option("--max-wall", sw.max_wall, "seconds of wall time after which a point's run stops as failed "
                                               "(harness run --max-wall; 0: no limit)")
        ->capture_default_str();
    cmd->add_flag("--list", sw.list, "print one `harness run` command per point and exit");
    cmd->add_option("--index", sw.index, "run only point I (0-based), then merge runs.csv");
    cmd->add_flag("--merge", sw.merge, "run nothing; rewrite DIR/runs.csv from the points already complete");
    cmd->add_option("--compare", sw.compare, "passed to every run: the reference to measure the error against");
    cmd->add_flag("--baseline", sw.baseline, "also run the scene with no contact force (every pair's force 0), once per "
                                             "combination of the grid's values outside contacts.*: runs.csv then says "
                                             "whether each point helps (error at least 10 % below it, with --compare)");
  }
  int exec(const char* argv0) {
    sw.scene = resolve_scene(scene);
    sw.scene_arg = scene;
    std::error_code ec;
    sw.self = fs::read_symlink("/proc/self/exe", ec).string();
    if (ec) sw.self = argv0;
    if (sw.jobs < 1) throw InputError("-j", "must be >= 1");
    if (cmd->count("--index") && sw.index < 0) throw InputError("--index", "must be >= 0");
    return run_sweep(sw);
  }
};

struct BenchCommand {
  CLI::App* cmd = nullptr;
  BenchOptions bo;

  void setup(CLI::App& app) {
    cmd = app.add_subcommand("bench", "time detection, references, steps and bandwidth limits on generated scenes; one CSV");
    cmd->add_flag("--quick", bo.quick, "stop at 10^5 nodes per body");
    cmd->add_option("--out", bo.out, "CSV file")->required();
    cmd->add_option("--sizes", bo.sizes, "nodes per body (default 1000,10000,100000[,1000000])")->delimiter(',');
    cmd->add_option("--threads", bo.threads, "thread counts to time")->delimiter(',')->capture_default_str();
    cmd->add_option("--min-time", bo.min_seconds, "seconds of repetitions per row (at least 3 reps)")->capture_default_str();
    cmd->add_flag("!--no-references", bo.references, "skip the fcl and cgal rows");
    cmd->add_option("--methods", bo.methods, "only these rows (CSV method names; default all)")->delimiter(',');
    cmd->add_option("--device", bo.device, "cpu (the rows above) or cuda (the device step and a copy, 10^3 to 10^7 "
                                           "nodes per body)")->capture_default_str();
  }
  int exec() {
    if (bo.device != "cpu") return run_device_bench(bo);
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
};

struct DetectionCommand {
  CLI::App* cmd = nullptr;
  DetectionOptions o;
  std::vector<std::string> scenes, sets;

  void setup(CLI::App& app) {
    cmd = app.add_subcommand("detection", "detection alone, every detector on the same states, timed and scored "
                                          "against CGAL's exact sets (claim (d)); one CSV");
    cmd->add_option("scenes", scenes, "scenes whose runs give the states (default: sphere_collision, "
                                      "cylinder_press, implant_expansion unless --sizes is given)");
    cmd->add_option("--out", o.out, "CSV file")->required();
    cmd->add_option("--set", sets, "KEY=JSON override applied to every scene");
    cmd->add_option("--sizes", o.sizes, "generated bench scenes, nodes per body (their initial state)")->delimiter(',');
    cmd->add_option("--states", o.states, "states per scene, evenly spaced over its steps")->capture_default_str();
    cmd->add_option("--min-rounds", o.min_rounds, "timed rounds at least")->capture_default_str();
    cmd->add_option("--min-time", o.min_seconds, "seconds of timed rounds per source at least")->capture_default_str();
    cmd->add_option("--hash-cells", o.hash_cells,
                    "more rows of the spatial hash, its cell at these multiples of the automatic cell (the host's "
                    "mean surface edge), e.g. 0.5,2,4: the cell sweep")
        ->delimiter(',');
  }
  int exec() {
    if (o.states < 1) throw InputError("--states", "must be >= 1");
    if (o.min_rounds < 1) throw InputError("--min-rounds", "must be >= 1");
    if (!(o.min_seconds >= 0.0)) throw InputError("--min-time", "must be >= 0");
    for (long long n : o.sizes)
      if (n < 8) throw InputError("--sizes", "nodes per body must be >= 8");
    for (double f : o.hash_cells)
      if (!(f > 0.0) || !std::isfinite(f)) throw InputError("--hash-cells", "each multiple must be a positive number");
    if (scenes.empty() && o.sizes.empty()) scenes = {"sphere_collision", "cylinder_press", "implant_expansion"};
    for (const std::string& s : scenes) o.scenes.emplace_back(s, edited_scene(s, sets, false, 0, 1, false, 0.0));
    return run_detection(o);
  }
};

}  // namespace

// HARNESS_THREADS, when set, must be a whole number of threads from 1 to 1024.
void check_threads_env() {
  const char* s = std::getenv("HARNESS_THREADS");
  if (!s) return;
  char* end = nullptr;
  const long v = std::strtol(s, &end, 10);
  if (!*s || *end != '\0' || v < 1 || v > 1024)
    throw InputError("HARNESS_THREADS", std::string("expected a number of threads from 1 to 1024, got '") + s + "'");
}

int main(int argc, char** argv) {
  CLI::App app{"harness: soft bodies as nonlinear mass-spring models, collisions by the local voxel "
               "model of Nikolaev (2013), measured against FCL and CGAL"};
  app.require_subcommand(1);
  RunCommand run;
  run.setup(app);
  CLI::App* list = app.add_subcommand("list", "list the bundled scenes");
  CLI::App* schema = app.add_subcommand("schema", "print the scene format's JSON Schema (draft 2020-12)");
  CLI::App* outputs = app.add_subcommand("outputs", "print docs/outputs.md: the columns of steps.csv and timing.csv, "
                                         "the stability verdicts and summary.json's keys");
  CLI::App* rules = app.add_subcommand("rules", "print docs/scenes.md's tables of the force rules (core/collision/rules/: "
                                       "one file per rule), of the eliminators and of the detectors");
  SweepCommand sweep;
  sweep.setup(app);
  BenchCommand bench;
  bench.setup(app);
  ReferenceCommand reference;
  reference.setup(app);
  DetectionCommand detection;
  detection.setup(app);
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
    check_threads_env();
    if (list->parsed()) return cmd_list();
    if (schema->parsed()) return std::fputs(scene_schema_text().c_str(), stdout) < 0 ? 1 : 0;
    if (outputs->parsed()) return std::fputs(outputs_markdown().c_str(), stdout) < 0 ? 1 : 0;
    if (rules->parsed())
      return std::fputs((force_rules_markdown() + "\n" + eliminators_markdown() + "\n" + detectors_markdown()).c_str(),
                        stdout) < 0
                 ? 1
                 : 0;
    if (bench.cmd->parsed()) return bench.exec();
    if (sweep.cmd->parsed()) return sweep.exec(argv[0]);
    if (reference.cmd->parsed()) return reference.exec();
    if (detection.cmd->parsed()) return detection.exec();
    return run.exec();
  } catch (const InputError& e) {
    std::fprintf(stderr, "harness: error: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "harness: error: %s\n", e.what());
    return 1;
  }
}
