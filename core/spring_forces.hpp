// Spring and dashpot forces over the World's arrays: the hot loop of a step, one pass that reads
// each node and each spring once (core/simd/kernels.hpp, SpringEvalRun and SpringSumRun, say the
// operations).
#pragma once

#include "core/world.hpp"

#include <algorithm>
#include <atomic>
#include <memory>
#include <cstdint>
#include <vector>

namespace harness {

// Node-centric copy of the springs, built once per world: every node's half-edges in two lists,
// "upper" (to a higher node: the spring is evaluated there) and "lower" (to a lower node: it
// takes the upper half-edge's results through lo_slot), each in spring order, the rest length, its
// reciprocal and the stiffness copied beside the upper ones (sequential reads), and the box: per
// upper half-edge what the spring adds to that node (below).
//
// Why this layout. A pass evaluates every spring once, along the contiguous upper half-edges
// (its square root, division and, for the exponential law, expm1 are the step's arithmetic: in
// full SIMD lanes, nothing per node), then sums every node's box entries (contiguous for its upper
// half-edges, through lo_slot for its lower ones: no position is read twice), each node written
// by one thread (no scatter, no conflicts), in one order, the same for any thread count and
// instruction set (core/simd/kernels.hpp: four interleaved partial sums per node, upper then
// lower half-edges). The index arrays and the box carry 4 padding entries (the SIMD tails read
// them).
struct SpringGather {
  int nodes = -1;
  std::size_t springs = 0;
  std::vector<int> up_start, up_self, up_other;  // CSR, per node
  std::vector<double> up_rest, up_inv_rest, up_stiff;
  std::vector<int> lo_start, lo_slot;             // lo_slot: the same spring's upper half-edge
  // The box, per upper half-edge h: the force on its node c d (F), the dashpot's s d (G), the
  // Gershgorin rows (R), each x y z 0 at 4 h from box(F) (one aligned four-lane load in the
  // sums), and the energy (e).
  std::vector<double> F, G, R, e;
  // The first entry of box b (F, G or R): its first 32-byte boundary.
  static double* box(std::vector<double>& b);
  std::vector<int> up_spring;                     // the spring of each upper half-edge
  // Runs of upper half-edges of one body [begin, end): its law and dashpot apply to all.
  struct Run {
    int begin, end, body;
  };
  std::vector<Run> runs;
  bool mixed = false;  // a spring's ends lie in different bodies (hand-built worlds): laws per spring

  // The pass over T > 1 threads, in one of two ways.
  // Halo: part t takes the nodes [bounds[t], bounds[t + 1]) (about equal work: an upper half-edge,
  // evaluated and summed, weighs kUpWeight lower ones, summed) and evaluates, besides its nodes'
  // upper half-edges, its own copy (the halo) of every spring whose upper end lies in an earlier
  // part and whose lower end is one of its nodes: its lower half-edges read that copy (lo_slot
  // redirected), so that no part waits for another and no node's sum is deferred. A copy is the
  // same spring evaluated by the same operations: the same bits. The halo's entries are appended
  // to the up_ arrays and the box, past U and its padding (each split's after the last), and
  // evaluated by runs of one body.
  // Two phases, where the halo would copy more than a kHaloShare of the springs (a node order
  // whose springs reach far: surface nodes first, then the interior): the threads evaluate equal
  // ranges of upper half-edges, wait for each other once, then sum the nodes [bounds[t],
  // bounds[t + 1]) (equal numbers of half-edges).
  struct Split {
    int T = 0;
    bool two_phase = false;
    std::vector<int> bounds;      // T + 1 node bounds
    std::vector<int> lo_slot;     // halo: lo_slot, the halo's lower half-edges redirected to their copy
    std::vector<Run> halo;        // halo: runs of halo entries of one body, part by part
    std::vector<int> halo_start;  // halo: T + 1, part t's runs [halo_start[t], halo_start[t + 1])
  };
  std::vector<Split> splits;      // one per thread count used so far
  // The shared pass (spring_pass_shared): kChunks node ranges of about equal numbers of
  // half-edges, made on first use, and the team's claims on them: the even threads take chunks
  // from the front, the odd ones from the back (each thread's evaluations and sums then mostly
  // fall in the same chunks: its own cache), for the evaluations, then the sums.
  static constexpr int kChunks = 32;
  std::vector<int> chunk_bounds;
  struct Claims {
    // Per phase: the free chunks [front, back), front in the low 32 bits, back in the high.
    alignas(64) std::atomic<std::uint64_t> free[2];
  };
  std::shared_ptr<Claims> claims = std::make_shared<Claims>();
  static constexpr long long kUpWeight = 4;
  static constexpr double kHaloShare = 0.125;

  bool matches(const World& w) const { return nodes == w.num_nodes() && springs == w.springs.size(); }
  void build(const World& w);
  // The split for T > 1 threads, made on first use (it may grow the up_ arrays and the box).
  const Split& split(int T);
};

// What a force pass computes besides the forces.
struct SpringPassOut {
  Points* f = nullptr;                 // += springs (and dashpots), per node
  Points* f_spring = nullptr;          // = the springs' part per node (energy audit), or null
  Points* f_dashpot = nullptr;         // = the dashpots' part per node (energy audit), or null
  std::vector<double>* energy = nullptr;  // = per node, the energy of its upper springs, or null
  std::vector<Vec3>* rows = nullptr;   // += Gershgorin rows of the springs (stability guard), or null
};

// One pass over every node: the springs' forces when `springs`, the dashpots' (material.damping)
// when `dashpots` (f[i] = (f[i] + springs) + dashpots), and what `out` asks for besides. Mass
// damping is not here (add_mass_damping). Outputs must be sized to the node count.
void spring_pass(SpringGather& g, const World& w, bool springs, bool dashpots, const SpringPassOut& out);
// spring_pass shared out among the threads of an enclosing OpenMP parallel region, in chunks
// handed out as threads come free (a thread busy with other work, contact detection, joins when
// it is done): every thread of the team calls it, and it ends with the team at a barrier. The same
// numbers as spring_pass. spring_pass_shareable(g, w), on one thread before the region, makes g
// ready for it and says whether the world is large enough to share (else call spring_pass).
bool spring_pass_shareable(SpringGather& g, const World& w);
void spring_pass_shared(SpringGather& g, const World& w, bool springs, bool dashpots, const SpringPassOut& out);
// The node energies of spring_pass summed in a fixed order (chunks of 4096 nodes), J.
double sum_node_energy(const std::vector<double>& e);

// Convenience forms (tests, tools): a gather made for the call.
void add_spring_forces(const World& w, Points& f);
// Dashpots along springs (material.damping), then mass-proportional damping (material.mass_damping).
void add_damping_forces(const World& w, Points& f);
void add_spring_forces(SpringGather& g, const World& w, Points& f);
void add_damping_forces(SpringGather& g, const World& w, Points& f);
// -(a m) v per node of every body with mass_damping a.
void add_mass_damping(const World& w, Points& f);
// Elastic energy of every spring (J), the same value for any thread count.
double spring_potential(const World& w);
// The same with a kept gather and node-energy buffer (sized here once): no allocation per call.
double spring_potential(SpringGather& g, const World& w, std::vector<double>& e);
// Gershgorin row sums of |df/dx| of the springs (tangent stiffness k_t u u^T at the current
// strain, the compressive geometric term left out) added into rows (one per node).
void add_spring_stiffness_rows(const World& w, std::vector<Vec3>& rows);
void add_spring_stiffness_rows(SpringGather& g, const World& w, std::vector<Vec3>& rows);

}  // namespace harness
