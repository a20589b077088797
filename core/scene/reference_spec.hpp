// Which exact references measure a run (the scene's `references` section): the scene layer's
// record, which the measurement (core/measure.hpp) and the reference library read.
#pragma once

namespace harness {

struct ReferenceSpec {
  bool cgal = false;
  bool fcl = false;
  bool ccd = false;
  int every = 1;        // measure on steps that are multiples of `every`
  bool volume = false;  // penetration volume by corefinement (CGAL), slow
};

}  // namespace harness
