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
};

// One grid point: its overrides in grid order.
using SweepPoint = std::vector<std::pair<std::string, std::string>>;

// Parses the --grid options; values are split at top-level commas (commas inside [], {} or
// quotes stay), so JSON lists are values too. Throws InputError("--grid ...") on bad syntax.
std::vector<std::pair<std::string, std::vector<std::string>>> parse_grids(const std::vector<std::string>& grids);
std::vector<SweepPoint> expand_grid(const std::vector<std::pair<std::string, std::vector<std::string>>>& g);
// Folder name of a point: "key-value__key-value" with unsafe characters replaced by '_'.
std::string point_name(const SweepPoint& p);

int run_sweep(const SweepOptions& opt);
// Rewrites DIR/runs.csv from the point folders that hold a summary.json.
void merge_runs(const std::string& out_dir, const std::vector<SweepPoint>& points);

}  // namespace harness
