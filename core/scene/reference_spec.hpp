// Which exact references measure a run (the scene's `references` section): the scene layer's
// record, which the measurement (core/measure.hpp) and the reference library read.
#pragma once

namespace harness {

// No default values of its own (zero until made): the loader fills it from the key table's rows
// "references.*"; one built by hand starts from reference_spec_defaults() (scene.hpp).
struct ReferenceSpec {
  bool cgal = false;
  bool fcl = false;
  bool ccd = false;
  int every = 0;        // measure on steps that are multiples of `every` (>= 1 once made)
  bool volume = false;  // penetration volume by corefinement (CGAL), slow
};

}  // namespace harness
