#include "core/run/frames.hpp"

#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <stdexcept>

namespace harness {

namespace {

struct File {
  std::FILE* f;
  std::string path;
  explicit File(const std::string& p) : f(std::fopen(p.c_str(), "w")), path(p) {
    if (!f) throw std::runtime_error("cannot write " + path);
  }
  void close() {
    const bool ok = std::ferror(f) == 0;
    const int rc = std::fclose(f);
    f = nullptr;
    if (rc != 0 || !ok) throw std::runtime_error("cannot write " + path);
  }
  ~File() {
    if (f) std::fclose(f);
  }
};

// VTK XML "binary" data: base64 of a UInt64 byte count followed by the raw little-endian values.
std::string base64(const std::vector<unsigned char>& in) {
  static const char* tbl = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((in.size() + 2) / 3 * 4);
  for (std::size_t i = 0; i < in.size(); i += 3) {
    const unsigned b0 = in[i], b1 = i + 1 < in.size() ? in[i + 1] : 0u, b2 = i + 2 < in.size() ? in[i + 2] : 0u;
    out += tbl[b0 >> 2];
    out += tbl[((b0 & 3u) << 4) | (b1 >> 4)];
    out += i + 1 < in.size() ? tbl[((b1 & 15u) << 2) | (b2 >> 6)] : '=';
    out += i + 2 < in.size() ? tbl[b2 & 63u] : '=';
  }
  return out;
}

template <class T>
std::string encode(const std::vector<T>& values) {
  const std::uint64_t bytes = values.size() * sizeof(T);
  std::vector<unsigned char> buf(sizeof bytes + bytes);
  std::memcpy(buf.data(), &bytes, sizeof bytes);
  if (bytes) std::memcpy(buf.data() + sizeof bytes, values.data(), bytes);
  return base64(buf);
}

template <class T>
void array(std::FILE* f, const char* type, const char* name, int components, const std::vector<T>& v) {
  std::fprintf(f, "        <DataArray type=\"%s\"", type);
  if (name) std::fprintf(f, " Name=\"%s\"", name);
  std::fprintf(f, " NumberOfComponents=\"%d\" format=\"binary\">\n          %s\n        </DataArray>\n", components,
               encode(v).c_str());
}

}  // namespace

void write_vtk(const std::string& path, const World& w, int body, const std::string& title,
               const std::vector<std::uint8_t>* penetrating) {
  const Body& b = w.bodies[body];
  File out(path);
  std::FILE* f = out.f;
  std::fprintf(f, "# vtk DataFile Version 3.0\n%s\nASCII\nDATASET POLYDATA\nPOINTS %d double\n",
               title.c_str(), b.n_surface);
  // The scene's numbering (world.hpp: Body::scene_node): point q is the node the scene numbers q.
  for (int q = 0; q < b.n_surface; ++q) {
    const Vec3& p = w.x[b.begin + b.local_of_scene(q)];
    std::fprintf(f, "%.9g %.9g %.9g\n", p.x(), p.y(), p.z());
  }
  std::fprintf(f, "POLYGONS %zu %zu\n", b.faces.size(), 4 * b.faces.size());
  for (const Tri& t : b.faces)
    std::fprintf(f, "3 %d %d %d\n", b.scene_index(t[0]), b.scene_index(t[1]), b.scene_index(t[2]));
  if (penetrating) {
    std::fprintf(f, "POINT_DATA %d\nSCALARS penetrating int 1\nLOOKUP_TABLE default\n", b.n_surface);
    for (int q = 0; q < b.n_surface; ++q) std::fprintf(f, "%d\n", (*penetrating)[b.local_of_scene(q)] ? 1 : 0);
  }
  out.close();
}

void write_vtk_xml(const std::string& path, const World& w, int body, const FrameData& data, bool unstructured) {
  const Body& b = w.bodies[body];
  const int n = b.n_surface;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<double> pts(3 * n), disp(3 * n), vel(3 * n), force(3 * n, nan), sd(n, nan), pen(n, nan);
  for (int q = 0; q < n; ++q) {  // point q: the node the scene numbers q (Body::scene_node)
    const int s = b.local_of_scene(q), i = b.begin + s;
    for (int k = 0; k < 3; ++k) {
      pts[3 * q + k] = w.x[i][k];
      disp[3 * q + k] = w.x0.empty() ? nan : w.x[i][k] - w.x0[i][k];
      vel[3 * q + k] = w.v[i][k];
      if (!data.contact_force.empty()) force[3 * q + k] = data.contact_force[s][k];
    }
    if (data.signed_distance && static_cast<int>(data.signed_distance->size()) == n) sd[q] = (*data.signed_distance)[s];
    if (data.penetrating) pen[q] = (*data.penetrating)[s] ? 1.0 : 0.0;
  }
  const std::size_t m = b.faces.size();
  std::vector<std::int64_t> conn(3 * m), offsets(m);
  for (std::size_t t = 0; t < m; ++t) {
    for (int k = 0; k < 3; ++k) conn[3 * t + k] = b.scene_index(b.faces[t][k]);
    offsets[t] = static_cast<std::int64_t>(3 * (t + 1));
  }
  const char* kind = unstructured ? "UnstructuredGrid" : "PolyData";
  File out(path);
  std::FILE* f = out.f;
  std::fprintf(f, "<?xml version=\"1.0\"?>\n<VTKFile type=\"%s\" version=\"1.0\" byte_order=\"LittleEndian\" "
                  "header_type=\"UInt64\">\n  <%s>\n", kind, kind);
  if (unstructured)
    std::fprintf(f, "    <Piece NumberOfPoints=\"%d\" NumberOfCells=\"%zu\">\n", n, m);
  else
    std::fprintf(f, "    <Piece NumberOfPoints=\"%d\" NumberOfVerts=\"0\" NumberOfLines=\"0\" NumberOfStrips=\"0\" "
                    "NumberOfPolys=\"%zu\">\n", n, m);
  std::fprintf(f, "      <PointData Scalars=\"signed_distance\" Vectors=\"displacement\">\n");
  array(f, "Float64", "displacement", 3, disp);
  array(f, "Float64", "velocity", 3, vel);
  array(f, "Float64", "contact_force", 3, force);
  array(f, "Float64", "signed_distance", 1, sd);
  array(f, "Float64", "penetrating", 1, pen);
  std::fprintf(f, "      </PointData>\n      <Points>\n");
  array(f, "Float64", "Points", 3, pts);
  std::fprintf(f, "      </Points>\n      <%s>\n", unstructured ? "Cells" : "Polys");
  array(f, "Int64", "connectivity", 1, conn);
  array(f, "Int64", "offsets", 1, offsets);
  if (unstructured) array(f, "UInt8", "types", 1, std::vector<std::uint8_t>(m, 5));  // VTK_TRIANGLE
  std::fprintf(f, "      </%s>\n    </Piece>\n  </%s>\n</VTKFile>\n", unstructured ? "Cells" : "Polys", kind);
  out.close();
}

void write_pvd(const std::string& path, const std::vector<std::pair<double, std::string>>& frames) {
  const std::string tmp = path + ".tmp";
  {
    File out(tmp);
    std::fprintf(out.f, "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" "
                        "byte_order=\"LittleEndian\">\n  <Collection>\n");
    for (const auto& [t, file] : frames)
      std::fprintf(out.f, "    <DataSet timestep=\"%.17g\" group=\"\" part=\"0\" file=\"%s\"/>\n", t, file.c_str());
    std::fprintf(out.f, "  </Collection>\n</VTKFile>\n");
    out.close();
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) throw std::runtime_error("cannot write " + path);
}

}  // namespace harness
