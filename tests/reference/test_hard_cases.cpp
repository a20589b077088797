// The hard-case suite (experiments/scenes/hard/): each scene must stay finite, keep its
// kinetic energy under a documented bound, close its energy audit, and either keep its residual
// depth under a bound or show the failure mode it is built to provoke, counted: tunnelled nodes,
// or the unstable class it is built to provoke (the run's stability verdict, core/run/window.hpp:
// contact that keeps putting energy in, "injects", or nodes chattering above the stated length,
// "chatters").
// Bounds are 1.5 times the values measured (see the comment of each row); they are not physical
// limits but regression guards on measured behaviour.
#include "scene_runner.hpp"

#include <catch2/catch.hpp>

#include <cmath>

using namespace harness;
using namespace harness::testing;

namespace {
struct HardCase {
  const char* name;
  const char* offset;     // a --set override (a scene a hair from a knife edge), or null
  double ke_peak_max;     // J
  double depth_peak_max;  // m; < 0: not asserted (the failure mode is asserted instead)
  int tunnelled_min;      // the failure mode: at least this many tunnelled nodes (0: none expected)
  int tunnelled_max;
  const char* unstable;   // the failure mode: this unstable class (null: a stable class expected)
};
// Measured (2026-11-23, materials from Young's modulus, gravity): KE peak, depth peak, tunnelled,
// contact's largest work over the energy put in.
const HardCase kCases[] = {
    // exponential tissue held at 100% strain, substeps: no contact.
    {"exp_large_strain", nullptr, 1.5 * 4.22e-3, -1.0, 0, 0, nullptr},
    // a ball at 60 m/s crosses 1.5 voxels per step: it tunnels - the failure mode.
    // Under the class of the fifth wave (window.hpp) the ball rings after it has gone through: its
    // nodes move 9.0 mm about their mean relative to its centre over the final window, above the
    // 1.95 mm voxel: "chatters" (measured 2026-11-29).
    {"fast_impact", nullptr, 1.5 * 4.10, -1.0, 100, 400, "chatters"},
    // one cell thick layer pressed by a driven probe.
    {"thin_layer", nullptr, 1.5 * 6.32e-4, 1.5 * 2.53e-4, 0, 40, nullptr},
    // a constant penalty force of 5 N, 100 times a typical one: contact injects 46 times the
    // energy put in; no true penetration.
    {"force_100x", nullptr, 1.5 * 1.91e-2, 1e-9, 0, 0, "injects"},
    // guest nodes exactly on host nodes (zero-length line): the initial depth must not grow;
    // pushing the initial overlap apart, contact injects. A knife edge: the line has no direction,
    // so the first pushes follow the fallbacks and then rounding: exactly coincident, the force
    // pass's summation order of 2026-11-24 pushes 22 guest nodes through the host's pinned
    // bottom (KE peak 1.82e-4 J; the order before it: none, 2.69e-5 J); offset by 1e-12 m, both
    // orders give 2.2e-5 J and none (the row below). Both outcomes are asserted. The earlier rate
    // read both "injects"; under the class of the fifth wave (window.hpp) the first is steady (its
    // nodes move 2.0 mm about their means, below the 3.9 mm voxel; the contact puts nothing in over
    // the window: its failure is its tunnelling), the offset row injects (2.9 % of the stored
    // energy per time scale, limit 2 %) (measured 2026-11-29).
    {"coincident_nodes", nullptr, 1.5 * 1.82e-4, 5.0e-3 * 1.0001, 0, 33, nullptr},
    {"coincident_nodes", "[0.005000000001,0.005,0.005]", 1.5 * 2.20e-5, 5.0e-3 * 1.0001, 0, 0, "injects"},
    // nearest host points collinear (a one-cell bar): no true penetration at all; but over the final
    // window the contact's mean power is 0.10 of the power put in: it keeps injecting (its
    // cumulative work, 4.4 % of the energy put in, read as no injection under the old rule). The
    // class of the fifth wave calls it steady: its nodes move 2.8 mm about their means, below the
    // 3.9 mm voxel, and the contact puts in 0.13 % of the stored energy per time scale.
    {"collinear_plane", nullptr, 1.5 * 1.42e-4, 1e-9, 0, 0, nullptr},
    // the probe leaves and re-enters the grid region.
    {"leave_reenter", nullptr, 1.5 * 1.16e-3, 1.5 * 5.69e-3, 0, 0, nullptr},
    // voxels (0.5 mm) much smaller than the node spacing (5 mm): contacts are missed, the probe
    // sinks in.
    {"tiny_voxels", nullptr, 1.5 * 7.02e-5, 1.5 * 5.21e-3, 0, 0, nullptr},
};
}  // namespace

TEST_CASE("hard cases stay numerically stable", "[hard]") {
  for (const HardCase& c : kCases) {
    std::vector<std::pair<std::string, std::string>> ov;
    if (c.offset) ov.emplace_back("bodies.1.shape.min", c.offset);
    const SceneRun r = run_scene_measured(std::string("hard/") + c.name, ov, 10);
    INFO(c.name << ": finite " << r.finite << " (" << r.failure << "), KE peak " << r.ke_peak << " J, depth peak "
                << r.max_depth_peak << " m, tunnelled " << r.tunnelled << ", contacts " << r.contacts_total
                << ", contact work / energy in " << r.contact_injection << ", verdict " << r.verdict << " (chatter "
                << r.chatter_amplitude << " m of " << r.chatter_length << " m, contact input share "
                << r.contact_input_share << ", earlier rate " << r.contact_power_ratio << "), balance error "
                << r.balance_error);
    WARN(c.name << ": KE peak " << r.ke_peak << " J, depth peak " << r.max_depth_peak << " m, final true penetration "
                << r.true_pen_final << ", tunnelled " << r.tunnelled << ", contact work / energy in "
                << r.contact_injection << ", balance error " << r.balance_error);
    REQUIRE(r.finite);
    CHECK(r.ke_peak <= c.ke_peak_max);
    if (c.depth_peak_max >= 0.0) CHECK(r.max_depth_peak <= c.depth_peak_max);
    CHECK(r.tunnelled >= c.tunnelled_min);
    CHECK(r.tunnelled <= c.tunnelled_max);
    if (c.unstable) {
      CHECK(r.verdict == c.unstable);
    } else {
      CHECK((r.verdict == "settled" || r.verdict == "steady" || r.verdict == "forced"));
    }
    CHECK(std::fabs(r.balance_error) < 0.01);  // the audit closes
  }
}
