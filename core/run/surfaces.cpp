#include "core/run/surfaces.hpp"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace harness {

namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
}  // namespace

int SurfaceState::body(const std::string& name) const {
  for (std::size_t b = 0; b < bodies.size(); ++b)
    if (bodies[b] == name) return static_cast<int>(b);
  return -1;
}

SurfaceState surface_state(const World& w, int step, double time, const std::vector<std::vector<double>>& sd) {
  SurfaceState s;
  s.step = step;
  s.time = time;
  for (std::size_t b = 0; b < w.bodies.size(); ++b) {
    const Body& body = w.bodies[b];
    s.bodies.push_back(body.name);
    // In the scene's numbering (Body::scene_node): row q is the node the scene numbers q.
    // Worlds built without rest positions (tests, hand-made states) record x as x0.
    const auto& rest = w.x0.size() == w.x.size() ? w.x0 : w.x;
    const bool has_sd = b < sd.size() && static_cast<int>(sd[b].size()) == body.n_surface;
    s.x.emplace_back(), s.x0.emplace_back(), s.sd.emplace_back();
    for (int q = 0; q < body.n_surface; ++q) {
      const int i = body.local_of_scene(q);
      s.x.back().push_back(w.x[body.begin + i]);
      s.x0.back().push_back(rest[body.begin + i]);
      s.sd.back().push_back(has_sd ? sd[b][static_cast<std::size_t>(i)] : kNaN);
    }
  }
  return s;
}

void write_surfaces(const std::string& path, const SurfaceState& s) {
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (!f) throw std::runtime_error("cannot write " + path);
  std::fprintf(f, "body,node,x,y,z,x0,y0,z0,signed_distance\n");
  for (std::size_t b = 0; b < s.bodies.size(); ++b)
    for (std::size_t i = 0; i < s.x[b].size(); ++i) {
      const Vec3& p = s.x[b][i];
      const Vec3 q = b < s.x0.size() ? s.x0[b][i] : p;
      std::fprintf(f, "%s,%zu,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,", s.bodies[b].c_str(), i, p.x(), p.y(), p.z(), q.x(),
                   q.y(), q.z());
      if (std::isfinite(s.sd[b][i])) std::fprintf(f, "%.17g", s.sd[b][i]);
      std::fputc('\n', f);
    }
  const bool ok = std::ferror(f) == 0;
  if (std::fclose(f) != 0 || !ok) throw std::runtime_error("cannot write " + path);
}

SurfaceState read_surfaces(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path, "cannot read (no surfaces.csv: not a finished run or reference)");
  SurfaceState s;
  std::string line;
  std::getline(in, line);
  if (line != "body,node,x,y,z,x0,y0,z0,signed_distance") throw InputError(path + ":1", "not a surfaces.csv header");
  int row = 1;
  while (std::getline(in, line)) {
    ++row;
    if (line.empty()) continue;
    std::vector<std::string> f;
    std::stringstream ss(line);
    std::string cell;
    while (std::getline(ss, cell, ',')) f.push_back(cell);
    if (line.back() == ',') f.emplace_back();
    if (f.size() != 9) throw InputError(path + ":" + std::to_string(row), "expected 9 fields");
    int b = s.body(f[0]);
    if (b < 0) {
      s.bodies.push_back(f[0]);
      s.x.emplace_back();
      s.x0.emplace_back();
      s.sd.emplace_back();
      b = static_cast<int>(s.bodies.size()) - 1;
    }
    try {
      if (std::stoul(f[1]) != s.x[b].size()) throw std::invalid_argument("node out of order");
      s.x[b].emplace_back(std::stod(f[2]), std::stod(f[3]), std::stod(f[4]));
      s.x0[b].emplace_back(std::stod(f[5]), std::stod(f[6]), std::stod(f[7]));
      s.sd[b].push_back(f[8].empty() ? kNaN : std::stod(f[8]));
    } catch (const std::exception& e) {
      throw InputError(path + ":" + std::to_string(row), std::string("malformed row (") + e.what() + ")");
    }
  }
  return s;
}

TrajectoryWriter::TrajectoryWriter(const std::string& path, const World& w) : path_(path) {
  f_ = std::fopen(path.c_str(), "wb");
  if (!f_) throw std::runtime_error("cannot write " + path);
  std::fwrite("HTRJ", 1, 4, f_);
  const std::int32_t version = 1, nb = static_cast<std::int32_t>(w.bodies.size());
  std::fwrite(&version, sizeof version, 1, f_);
  std::fwrite(&nb, sizeof nb, 1, f_);
  for (const Body& b : w.bodies) {
    const std::int32_t len = static_cast<std::int32_t>(b.name.size()), n = b.n_surface;
    std::fwrite(&len, sizeof len, 1, f_);
    std::fwrite(b.name.data(), 1, b.name.size(), f_);
    std::fwrite(&n, sizeof n, 1, f_);
  }
}

TrajectoryWriter::~TrajectoryWriter() {
  if (f_) std::fclose(f_);
}

void TrajectoryWriter::record(const SurfaceState& s) {
  const std::int32_t step = s.step;
  std::fwrite(&step, sizeof step, 1, f_);
  std::fwrite(&s.time, sizeof s.time, 1, f_);
  for (std::size_t b = 0; b < s.x.size(); ++b)
    for (std::size_t i = 0; i < s.x[b].size(); ++i) {
      const double v[4] = {s.x[b][i].x(), s.x[b][i].y(), s.x[b][i].z(), s.sd[b][i]};
      std::fwrite(v, sizeof(double), 4, f_);
    }
}

void TrajectoryWriter::close() {
  const bool ok = std::ferror(f_) == 0;
  const int rc = std::fclose(f_);
  f_ = nullptr;
  if (rc != 0 || !ok) throw std::runtime_error("cannot write " + path_);
}

std::vector<SurfaceState> read_trajectory(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "cannot read");
  auto get = [&](void* p, std::size_t n) {
    in.read(static_cast<char*>(p), static_cast<std::streamsize>(n));
    return static_cast<bool>(in);
  };
  char magic[4];
  std::int32_t version = 0, nb = 0;
  if (!get(magic, 4) || std::memcmp(magic, "HTRJ", 4) != 0 || !get(&version, 4) || version != 1 || !get(&nb, 4) ||
      nb < 0 || nb > 1000000)
    throw InputError(path, "not a harness trajectory (version 1)");
  SurfaceState head;
  std::vector<std::int32_t> counts;
  for (std::int32_t b = 0; b < nb; ++b) {
    std::int32_t len = 0, n = 0;
    if (!get(&len, 4) || len < 0 || len > 4096) throw InputError(path, "malformed header");
    std::string name(static_cast<std::size_t>(len), '\0');
    if (!get(name.data(), name.size()) || !get(&n, 4) || n < 0) throw InputError(path, "malformed header");
    head.bodies.push_back(name);
    counts.push_back(n);
  }
  std::vector<SurfaceState> out;
  std::int32_t step = 0;
  while (get(&step, 4)) {
    SurfaceState s = head;
    s.step = step;
    if (!get(&s.time, 8)) throw InputError(path, "truncated record");
    for (std::int32_t b = 0; b < nb; ++b) {
      s.x.emplace_back(static_cast<std::size_t>(counts[b]));
      s.sd.emplace_back(static_cast<std::size_t>(counts[b]));
      for (std::int32_t i = 0; i < counts[b]; ++i) {
        double v[4];
        if (!get(v, sizeof v)) throw InputError(path, "truncated record");
        s.x[b][i] = Vec3(v[0], v[1], v[2]);
        s.sd[b][i] = v[3];
      }
    }
    out.push_back(std::move(s));
  }
  return out;
}

}  // namespace harness
