// `harness reference SCENE --out DIR`: the converged reference solution of a scene, the answer
// the methods are judged against (core/run/compare.hpp). The scene is run with exact detection
// (CGAL), contact both ways (`--one-sided`: the guest's nodes kept out of the host only, as the
// paper's model does), and the depth-proportional penalty k_c x depth along the other surface's
// outward normal at its closest point (reactions by barycentric weights: a conservative penalty
// that settles), to the scene's own settling tolerance (time.settle, the same tolerance its runs
// settle to). Level i runs at dt_0 / 2^i with k_c = k_0 2^i over the same physical time (every
// step count of the scene scaled) under the stability guard "substep": no step of any level runs
// above 0.9 dt_crit, the penalty's stiffness counted (stability.hpp), and each level records its
// guard figures. The loop stops when at least min_levels levels have run and the settled surface
// vertices of the last two differ by less than the tolerance (default 0.05 mm) anywhere, or
// after max_levels levels. From three levels on, the observed order of convergence
// p = log2(change_{i-1} / change_i) and the Richardson estimate of the last level's error,
// change_i / (2^p - 1), are recorded.
// DIR holds the last level's run (steps.csv, summary.json, surfaces.csv, frames/) and every
// level's in DIR/levels/<i>/; summary.json's "reference" records each level's dt, k_c, steps,
// residual, change, guard figures and order, and `converged`. An unconverged reference exits 0
// but says so in its summary, on stderr, and in every comparison that uses it.
#pragma once

#include "core/run/run_scene.hpp"
#include "core/scene/scene.hpp"

#include <string>

namespace harness {

struct ReferenceOptions {
  std::string out_dir;
  double tolerance = 5e-5;   // m
  int max_levels = 5;
  int min_levels = 3;        // levels at least (two changes: an observed order)
  bool one_sided = false;    // contact one way only (the guest kept out of the host)
  double stiffness = 0.0;    // k_0, N/m; 0: the scene's penalty stiffness, else 100 x the mean
                             // spring stiffness of the pair's host
  RunOptions run;            // measurer, exact detectors, versions
  bool progress = false;
};

int run_reference(const Scene& scene, const ReferenceOptions& opt);

}  // namespace harness
