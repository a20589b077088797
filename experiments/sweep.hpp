// `harness sweep SCENE --grid KEY=V1,V2,... [--grid ...] --out DIR [-j N] [--list] [--index I] [--merge]`
// The Cartesian product of the grid values; one `harness run` folder per point under DIR, named
// by its parameters; DIR/runs.csv merges one row per point: its parameters, then its summary
// figures. Points run as child processes of this program (`harness run ...`), so that -j N
// runs N at once and `--list` / `--index I` let any scheduler run one point per task.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace harness {

// The default wall-time cap of a sweep's point (harness run --max-wall): a point that runs longer
// fails and says so, instead of holding the sweep for hours (a user's sweep point once took 461 s
// of 268,126 substeps per step before it failed).
constexpr double kSweepMaxWall = 1800.0;

struct SweepOptions {
  std::string scene;        // path (already resolved)
  std::string scene_arg;    // as the user gave it (used in --list commands)
  std::vector<std::string> grids;  // "KEY=V1,V2,..."
  std::vector<std::string> sets;   // fixed overrides applied to every point ("KEY=JSON")
  std::string out_dir;
  int jobs = 1;
  bool list = false;
  int index = -1;  // run only this point (then merge whatever points are complete)
  bool merge = false;  // run nothing: rewrite runs.csv from the complete points
  std::string self;  // path of this executable
  std::string compare;  // --compare DIR passed to every run
  bool baseline = false;  // --baseline: the no-force runs "helps" is judged against (sweep_jobs)
  double max_wall = kSweepMaxWall;  // --max-wall passed to every run (0: no limit)
};

// One grid point: its overrides in grid order.
using SweepPoint = std::vector<std::pair<std::string, std::string>>;

// Parses the --grid options; values are split at top-level commas (commas inside [], {} or
// quotes stay), so JSON lists are values too. Throws InputError("--grid ...") on bad syntax.
std::vector<std::pair<std::string, std::vector<std::string>>> parse_grids(const std::vector<std::string>& grids);
std::vector<SweepPoint> expand_grid(const std::vector<std::pair<std::string, std::vector<std::string>>>& g);
// Folder name of a point: "key-value__key-value" with unsafe characters replaced by '_'.
std::string point_name(const SweepPoint& p);

// A run of the sweep: a grid point, or with --baseline a no-force run ("no_force[__...]": once per
// combination of the grid's values outside contacts.*, every pair's force 0), after the points.
struct SweepJob {
  SweepPoint sets;       // its overrides (after the fixed --set ones)
  std::string name;      // its folder under DIR
  int baseline = -1;     // a grid point's no-force job (index into the jobs), -1: none
  bool no_force = false;
};
std::vector<SweepJob> sweep_jobs(const std::vector<SweepPoint>& points, bool baseline, std::size_t pairs);

// "helps": a run's window error (mean of the largest position error) at most this share of its
// no-force run's, or its window depth at most this share with an error no larger (the studies'
// rule: scripts/harness_results/rules.py USEFUL).
inline constexpr double kHelpsShare = 0.9;

int run_sweep(const SweepOptions& opt);
// Rewrites DIR/runs.csv from the job folders that hold a summary.json: per row the grid values,
// the summary figures (merged_figures), and no_force_error, helps, useless (tunnels, or no better
// than no force).
void merge_runs(const std::string& out_dir, const std::vector<SweepPoint>& points, const std::vector<SweepJob>& jobs);

}  // namespace harness
