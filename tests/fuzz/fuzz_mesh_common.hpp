// The OFF and OBJ targets: read_surface_text on arbitrary bytes; an accepted surface must be a
// closed, outward-oriented 2-manifold that the shape generator turns into a model (shell and
// volume fill) without complaint.
#pragma once

#include "core/mesh.hpp"
#include "core/shapes/shapes.hpp"
#include "tests/fuzz/fuzz_common.hpp"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>

namespace harness_fuzz {

inline void check_model(const harness::ShapeModel& m) {
  const int n = static_cast<int>(m.nodes.size());
  FUZZ_CHECK(m.n_surface > 0 && m.n_surface <= n);
  FUZZ_CHECK(m.node_volume.size() == m.nodes.size());
  for (const harness::Vec3& p : m.nodes) FUZZ_CHECK(p.allFinite());
  for (const harness::Tri& t : m.faces)
    for (int v : t) FUZZ_CHECK(v >= 0 && v < m.n_surface);
  for (const harness::Edge& e : m.springs)
    FUZZ_CHECK(e[0] >= 0 && e[0] < n && e[1] >= 0 && e[1] < n && e[0] != e[1]);
  FUZZ_CHECK(m.volume > 0.0);
}

inline int fuzz_mesh(const std::uint8_t* data, std::size_t size, bool obj) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  harness::SurfaceMesh mesh;
  try {
    mesh = harness::read_surface_text(text, obj ? "fuzz.obj" : "fuzz.off", obj);
  } catch (const harness::InputError& e) {
    fuzz_note(e.what());
    return 0;
  }
  const harness::SurfaceReport rep = harness::check_surface(mesh);
  FUZZ_CHECK(rep.ok());
  // The reader accepted it, so the generator must too (the reader's checks are the stricter).
  for (const harness::Fill fill : {harness::Fill::shell, harness::Fill::volume})
    check_model(harness::make_from_surface(mesh, 1.0, harness::Vec3::Zero(), fill));
  fuzz_note("accepted: " + std::to_string(mesh.V.size()) + " vertices, " +
            std::to_string(mesh.F.size()) + " triangles");
  return 0;
}

}  // namespace harness_fuzz
