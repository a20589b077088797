// `harness reference SCENE --out DIR`: the converged reference solution of a scene, the answer
// the methods are judged against (core/run/compare.hpp). The scene is run with exact detection
// (CGAL), contact both ways, and the depth-proportional penalty k_c x depth along the other
// surface's outward normal at its closest point (reactions by barycentric weights: a
// conservative penalty that settles), to a tight equilibrium (time.settle's tolerance / 100).
// Level i runs at dt_0 / 2^i with k_c = k_0 2^i over the same physical time (every step count of
// the scene scaled); the loop stops when the settled surface vertices of two consecutive levels
// differ by less than the tolerance (default 0.05 mm) anywhere, or after max_levels levels.
// DIR holds the last level's run (steps.csv, summary.json, surfaces.csv, frames/) and every
// level's in DIR/levels/<i>/; summary.json's "reference" records each level's dt, k_c, steps,
// residual and change, and `converged`. An unconverged reference exits 0 but says so in its
// summary, on stderr, and in every comparison that uses it.
#pragma once

#include "core/run.hpp"
#include "core/scene.hpp"

#include <string>

namespace harness {

struct ReferenceOptions {
  std::string out_dir;
  double tolerance = 5e-5;   // m
  int max_levels = 5;
  double stiffness = 0.0;    // k_0, N/m; 0: the scene's penalty stiffness, else 100 x the mean
                             // spring stiffness of the pair's host
  RunOptions run;            // measurer, exact detectors, versions
  bool progress = false;
};

int run_reference(const Scene& scene, const ReferenceOptions& opt);

}  // namespace harness
