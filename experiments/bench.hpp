// `harness bench [--quick] --out FILE`: time per step of the voxel model, its references and
// the memory-bandwidth limits, on generated contact scenes of 10^3 .. 10^6 nodes per body, with
// one and with two threads; one CSV from one process (docs/usage.md).
//
// Scene of size N (make_bench_scene): host = a box lattice layer of about N nodes, a cells wide
// in x and y and a/4 thick (1 mm spacing, pinned at -z); guest = a surface of about N nodes (the
// issue's "guest surface pressed into a host layer"): a closed cylinder shell lying along x,
// radius 0.15 of the layer's width, length 2 pi radius (square cells, about sqrt(N) segments and
// rings, fan caps), its lowest fifth of a radius pressed into the layer (offset by fractions of
// a spacing, so no node lies on a lattice plane of the host). Every guest node is a surface
// vertex, so FCL, CGAL and the voxel model see the same guest nodes.
// Cubic springs (beta = 2), effects springs, pins, contact; voxel size automatic, region half,
// line eliminator with a constant force; dt far below the stability limit, so the state (and the
// contact count) hardly changes between repetitions.
//
// Methods (one row each per size and thread count):
//   voxel_detect            Collision::detect: grid re-attached, filled and every guest node
//                           looked up (the paper's detection).
//   voxel_detect_eliminate  Collision::step: detection plus line elimination.
//   voxel_exact_detect      the same with detector voxel_exact (detectors/voxel_exact.hpp): the
//                           paper's grid of the host's surface vertices, every guest node near
//                           a listed vertex given its closest host triangle and inside verdict.
//   voxel_exact_detect_eliminate  its Collision::step (the scene's line rule, constant force,
//                           along the exact normal).
//   fcl                     FclSurface::update of both surfaces (vertex replacement and refit)
//                           plus intersecting_pairs (every intersecting triangle pair, counted).
//   cgal                    CgalSurface::update of the host (AABB tree rebuilt) plus the exact
//                           inside test of every guest node (the ground truth of detection).
//   stream_positions        one pass reading every node position of both bodies once: the
//                           memory-bandwidth limit of detection.
//   step                    Simulation::step: springs, pins, contact (detect and eliminate),
//                           integration; timed over blocks of Simulation::kGuardEvery steps, so
//                           that the periodic stability check (critical_dt) is in the figure.
//   stream_step             one pass reading every spring (ends, rest length) and every node's
//                           position, velocity, force, inverse mass and kinematic flag, and
//                           writing every position and velocity: the memory limit of a step.
//   arith_floor             one square root and one division per spring, in the force pass's
//                           SIMD lanes (simd::Kernels::sqrt_div): the arithmetic limit of a step
//                           (correctly rounded IEEE operations, which no layout removes).
//   pass_floor              both ends of every spring gathered as the force pass gathers them
//                           (simd::Kernels::pass_floor), their distance's square root and one
//                           division: what any force pass must do per spring, nothing stored.
//   bullet_collide          Bullet's collision step on the same two bodies as soft bodies
//                           (reference/bullet_engine.hpp, BulletCollisionBench): their node and
//                           face trees refitted and the vertex-face (VF_SS) pass.
// fcl, cgal and bullet_collide are single-threaded libraries: they are timed with one thread only.
// Times are medians over repetitions (at least 3, and at least min_seconds per thread count); the
// thread counts of a method take turns repetition by repetition, so that a slow phase of the
// shared machine hits them alike and the speed-ups hold. A reference whose first repetition
// takes longer than single_rep_seconds is measured once.
#pragma once

#include <string>
#include <vector>

namespace harness {

struct BenchOptions {
  std::string device = "cpu";      // cpu: the rows below; cuda: the device rows (run_device_bench)
  bool quick = false;                // stop at 10^5 nodes per body
  std::string out;                   // CSV path
  std::vector<long long> sizes;      // nodes per body; empty = 10^3 .. 10^6 (10^5 with quick)
  std::vector<int> threads = {1, 2};
  double min_seconds = 0.2;          // per method, point and thread count
  int min_reps = 3;
  double single_rep_seconds = 2.0;   // references slower than this are measured once
  bool references = true;            // fcl and cgal rows (when the build has them)
  std::vector<std::string> methods;  // only these rows (names as in the CSV); empty = all
  bool progress = true;              // one line per row on stderr
};

// The median of repeated timings (the mean of the middle two for an even count); the bench's and
// `harness detection`'s.
double median_of(std::vector<double> v);

// The method names, in the order of the rows.
const std::vector<std::string>& bench_methods();

// Runs the benchmark and writes the CSV. Returns 0.
int run_bench(const BenchOptions& options);

struct Scene;
// The generated contact scene of about n nodes per body (above). With `scene_laws`, the same
// lattice with what the bundled scenes write: the exponential law (nonlinearity 3), a dashpot
// along each spring (damping 0.0005) and mass damping 20 (the `damping` effect), gravity.
Scene make_bench_scene(long long n, bool scene_laws = false);

// `harness bench --device cuda`: per size, the device step of the bench scene (rows `step`,
// median of timed batches of steps, each batch waited for at its end: throughput) and `copy` (one
// device-to-device copy of half the step's bytes, so that it reads and writes the bytes
// stream_step counts), each row naming the device. Returns the exit status.
int run_device_bench(const BenchOptions& o);

}  // namespace harness
