// `harness detection [SCENE...] [--sizes N,...] --out FILE`: claim (d) of the paper as it states
// it ("collision search using space voxelization is one of the most fast"): detection alone, per
// detector, on the same states, beside its quality against CGAL's exact sets.
//
// States. A scene is run as it is written (its own contact response drives it; --set edits every
// scene alike) and `states` states are kept, evenly spaced over its steps (steps k * steps / K,
// k = 1..K). A generated bench scene of N nodes per body (make_bench_scene, bench.hpp) gives one
// state, its initial one. Every detector sees exactly these positions.
//
// Detectors, per contact pair, each configured once on the rest state as a run configures it
// (the pair's own region, margin, host nodes):
//   voxel        the paper's grid at the pair's voxel size (its automatic one when "auto"), and at
//                half and twice that size (rows "voxel x0.5", "voxel x2");
//   voxel_exact  the completed model at its automatic voxel size;
//   hash         spatial hashing at its automatic cell;
//   fcl, cgal    the exact detectors (cgal's contacts are the truth itself).
// Time: one-sided detection (Collision::detect, the guest's nodes against the host, as the paper
// detects), one thread, in rounds: a round calls every detector on every state, the detectors
// taking turns (their order rotated every round), so a slow phase of the shared machine hits them
// alike. Each detector is called twice in a row on a state: the first call comes after the other
// detectors ran (cold caches, its seeds from another state: detect_us), the second at once on the
// same state (warm: detect_warm_us); a run's step lies between (its physics pass runs between two
// detections, on states a step apart). A detector's time is the median over rounds of its mean
// over the states; min and max over rounds are its spread. Rounds: at least min_rounds, and until
// min_seconds have passed.
// Quality: each detector run two-sided on every state (the guest's nodes against the host's
// surface and the host's nodes against the guest's), scored node by node against CGAL's two-sided
// sets (nodes strictly inside the other body's closed surface, interior nodes too, as a run's
// recorder scores them): tp, fp, fn summed over the states, guest and host apart. Recall
// tp / (tp + fn) and precision tp / (tp + fp) are empty where their denominator is 0.
//
// The CSV is written to FILE.tmp and renamed when complete; on SIGINT or SIGTERM the command stops
// between two states, removes FILE.tmp and exits 128 + the signal (FILE untouched).
#pragma once

#include "core/scene/scene.hpp"

#include <string>
#include <utility>
#include <vector>

namespace harness {

struct DetectionOptions {
  std::vector<std::pair<std::string, Scene>> scenes;  // (label, scene as edited)
  std::vector<long long> sizes;                       // generated bench scenes, nodes per body
  int states = 20;
  int min_rounds = 5;
  double min_seconds = 0.5;  // of timed rounds per source
  std::vector<double> hash_cells;  // more rows of the spatial hash: its cell at these multiples of the automatic one
  std::string out;
  bool progress = true;
};

// The CSV's columns, in order.
const std::vector<std::string>& detection_columns();

// Runs it and writes the CSV. Returns 0, or 128 + the signal when interrupted. Throws
// std::runtime_error where this program has no reference library (the truth is CGAL's).
int run_detection(const DetectionOptions& options);

}  // namespace harness
