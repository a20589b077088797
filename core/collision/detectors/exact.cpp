// The exact detectors' names (their code is in reference/, which links FCL and CGAL: core
// names them so that every program reads the same scenes; reference::make_exact_detector makes them).
#include "core/collision/detectors/collision_detector.hpp"

namespace harness {

HARNESS_DETECTOR(cgal) {
  DetectorDef d;
  d.name = "cgal";
  d.doc = "exact: CGAL's inside test of every guest node against the host's closed surface, the closest point and depth";
  d.exact = true;
  return d;
}

HARNESS_DETECTOR(fcl) {
  DetectorDef d;
  d.name = "fcl";
  d.doc = "exact: FCL's triangle pairs between the two surfaces, the vertices of intersecting triangles with their depth";
  d.exact = true;
  return d;
}

}  // namespace harness
