// `harness run`: simulates a scene and writes DIR/steps.csv (run/columns.hpp),
// DIR/summary.json (run/summary.hpp), DIR/surfaces.csv and DIR/trajectory.bin (run/surfaces.hpp),
// DIR/frames/ (run/frame_writer.hpp) and, with CGAL, DIR/penetration_episodes.csv. One loop:
// step, check, record (run/recorder.hpp), write; progress (run/progress.hpp), SIGINT and SIGTERM
// (run/signals.hpp), the outcome, the warnings and the end line (run/report.hpp).
#pragma once

#include "core/node_order.hpp"

#include "core/measure.hpp"
#include "core/run/report.hpp"
#include "core/scene/scene.hpp"
#include "core/simulation.hpp"

#include <cstdint>
#include <functional>
#include <map>
#include <string>

namespace harness {

struct RunOptions {
  std::string out_dir = "out";
  bool progress = false;                        // a progress line on stderr
  MeasurerFactory measurer;                     // empty: references unavailable in this program
  ExactDetectorMaker exact_detectors = nullptr;  // empty: detectors "cgal", "fcl" unavailable
  EngineMaker engine = nullptr;                  // --engine: a peer engine (engine.hpp); empty: the harness's own
  std::map<std::string, std::string> versions;  // extra library versions (FCL, CGAL)
  std::string compare_dir;                      // --compare: a reference or a finished run
  std::string compare_also_dir;                 // --compare-also: a second one (needs compare_dir)
  bool strict = false;                          // --strict: a warning is an error (exit 2)
  NodeOrder node_order = kDefaultNodeOrder;     // --node-order: the world's layout (node_order.hpp)
  // --ensemble K (run_ensemble): K members; a member's initial jitter and its seed (SimulationOptions).
  double max_wall_s = 0.0;  // --max-wall: a run past this wall time fails (0: no limit)
  int ensemble = 1;
  // Contact responses of the program's own by pair (SimulationOptions::responses; the Python
  // module's harness.run(response=...)); recorded as summary.json pairs[].response.
  std::vector<OwnResponse> responses;
  double jitter = 0.0;
  std::uint64_t jitter_seed = 0;
};

// The jitter of an ensemble's members: far below the mesh's precision (a file's coordinates carry 9
// significant digits), as a share of the body's rest spring length.
constexpr double kEnsembleJitter = 1e-9;

// `harness run --ensemble K`: K members that differ only in what a user cannot control. Member 0
// is the run as asked (DIR, as without --ensemble); member k >= 1 (DIR/members/k/) takes the next
// node order after the asked one (scene, rcm, morton, cycling) and an initial jitter of
// kEnsembleJitter with seed k. DIR/summary.json gains `ensemble`: the members' node orders, seeds,
// state hashes and classes (counts per class), and each figure's median and range over the members
// (the numbers of `window` and `pairs`, the final kinetic energy and residual); its
// `stability_verdict` is the class every member shares, or "flips". Exit status: member 0's, or the
// first other member's that is not 0.
int run_ensemble(const Scene& scene, const RunOptions& options);

// Exit status: 0 done, 3 the state became non-finite (last good state and summary written),
// 130 / 143 stopped by SIGINT / SIGTERM (outputs written, summary status "interrupted"),
// 2 with `strict` when a warning was found at the end (tunnelled nodes; outputs written).
// Throws InputError before anything is written when the scene cannot be built, or with
// `strict` when a start warning (run/warnings.hpp) is found. `outcome`, when given, receives what
// the run found (what summary.json was written from).
int run_scene(const Scene& scene, const RunOptions& options, RunOutcome* outcome = nullptr);

// One step with the run's checks: the state before it is kept, and when the step throws (the
// voxel region outgrew its cap) or leaves a non-finite state, it is put back and the reason is
// returned (empty: the step went through). `good_x`, `good_v` are scratch of the node count.
std::string checked_step(Simulation& sim, Points& good_x, Points& good_v);

// The steps of a run: time.steps, then with time.settle until the force residual has been
// within its tolerance for kSettleWindow steps in a row, or max_steps more steps. After each
// completed step, on_step(last) (last: the run ends with it). Stops at the first failed step, and
// (run_scene's handlers installed) after a step during which SIGINT or SIGTERM arrived.
struct StepsOutcome {
  std::string failure;  // empty: every step went through
  int failed_step = 0;
  bool settled = false;
  int settle_steps = 0;  // taken after time.steps
  int signal = 0;        // SIGINT or SIGTERM stopped the run after the last step (run_scene only)
  bool wall_limit = false;  // stopped by max_wall_s (failure says so; the state is finite)
};
// max_wall_s > 0: the run stops as failed (StepsOutcome::failure, the last step kept) once it has
// taken more wall time than that (--max-wall).
StepsOutcome run_steps(Simulation& sim, const std::function<void(bool last)>& on_step, double max_wall_s = 0.0);

// A step that fails names the blow-up behind it first: a body whose state is not finite, or that
// spans more than kBlowUpFactor times its rest size (empty when neither).
constexpr double kBlowUpFactor = 100.0;
std::string blow_up(const World& w);

}  // namespace harness
