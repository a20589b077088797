// The checks every generated or read surface of sphere topology must pass (check_surface).
#pragma once

#include "core/mesh.hpp"

#include <catch2/catch.hpp>

namespace harness::test {

// Closed, 2-manifold, outward, one component of Euler characteristic 2; returns the report.
inline SurfaceReport require_sphere_topology(const SurfaceMesh& m) {
  const SurfaceReport r = check_surface(m);
  INFO(r.problem);
  CHECK(r.ok());
  CHECK(r.closed);
  CHECK(r.manifold);
  CHECK(r.oriented);
  CHECK(r.euler == 2);
  CHECK(r.components == 1);
  CHECK(r.problem.empty());
  CHECK(r.signed_volume > 0.0);
  return r;
}

}  // namespace harness::test
