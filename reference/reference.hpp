// Public interface of the harness_reference library (FCL, libccd and CGAL adapters).
#pragma once

#include "reference/bullet_engine.hpp"      // make_bullet_engine(), bullet_version()
#include "reference/cgal_surface.hpp"       // inside_surface(), CgalSurface
#include "reference/exact_detectors.hpp"    // make_exact_detector()
#include "reference/measure_reference.hpp"  // make_reference_measurer(), reference_versions(),
                                            // reference_version_map()
