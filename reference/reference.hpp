// Public interface of the harness_reference library (FCL, libccd and CGAL adapters).
#pragma once

#include "reference/bullet_engine.hpp"      // make_bullet_engine(), bullet_version()
#include "reference/cgal_surface.hpp"       // inside_surface(), CgalSurface
#include "reference/exact_detectors.hpp"    // make_exact_detector()
#include "reference/measure_reference.hpp"  // make_reference_measurer(), reference_versions(),
                                            // reference_version_map()

#include "core/run/run_scene.hpp"

namespace harness {

// A program's RunOptions with this library's exact detectors, measurer and versions filled in
// (the command line's runs and the Python module's).
inline RunOptions with_references(RunOptions opt = {}) {
  opt.measurer = make_reference_measurer;
  opt.exact_detectors = make_exact_detector;
  opt.versions = reference_version_map();
  return opt;
}

}  // namespace harness
