#include "core/run/frames.hpp"

#include <cstdio>
#include <stdexcept>

namespace harness {

void write_vtk(const std::string& path, const World& w, int body, const std::string& title,
               const std::vector<std::uint8_t>* penetrating) {
  const Body& b = w.bodies[body];
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (!f) throw std::runtime_error("cannot write " + path);
  std::fprintf(f, "# vtk DataFile Version 3.0\n%s\nASCII\nDATASET POLYDATA\nPOINTS %d double\n",
               title.c_str(), b.n_surface);
  for (int s = 0; s < b.n_surface; ++s) {
    const Vec3& p = w.x[b.begin + s];
    std::fprintf(f, "%.9g %.9g %.9g\n", p.x(), p.y(), p.z());
  }
  std::fprintf(f, "POLYGONS %zu %zu\n", b.faces.size(), 4 * b.faces.size());
  for (const Tri& t : b.faces) std::fprintf(f, "3 %d %d %d\n", t[0], t[1], t[2]);
  if (penetrating) {
    std::fprintf(f, "POINT_DATA %d\nSCALARS penetrating int 1\nLOOKUP_TABLE default\n", b.n_surface);
    for (int v = 0; v < b.n_surface; ++v) std::fprintf(f, "%d\n", (*penetrating)[v] ? 1 : 0);
  }
  const bool ok = std::ferror(f) == 0;
  if (std::fclose(f) != 0 || !ok) throw std::runtime_error("cannot write " + path);
}

}  // namespace harness
