#include "core/run/frame_writer.hpp"

#include "core/collision/responses/force_rules.hpp"
#include "core/run/frames.hpp"

#include <cstdio>
#include <limits>

namespace harness {

namespace fs = std::filesystem;

namespace {

std::string xml_escape(const std::string& s) {
  std::string out;
  for (char ch : s) {
    switch (ch) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += ch;
    }
  }
  return out;
}

}  // namespace

Points contact_forces(const Simulation& sim) {
  const World& w = sim.world();
  Points f(static_cast<std::size_t>(w.num_nodes()), Vec3::Zero());
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (const Pair& pair : sim.pairs()) {
    if (pair.engine_contact) {  // a peer engine's position corrections: no force to report
      for (int b : {pair.spec.host, pair.spec.guest})
        for (int i = w.bodies[b].begin; i < w.bodies[b].end; ++i) f[i] = Vec3::Constant(nan);
      continue;
    }
    if (!pair.collision || !pair.collision->stepped()) continue;
    const Collision& c = *pair.collision;
    if (c.projects()) {
      for (int b : {pair.spec.host, pair.spec.guest})
        for (int i = w.bodies[b].begin; i < w.bodies[b].end; ++i) f[i] = Vec3::Constant(nan);
      continue;
    }
    scatter_pushes(f, c.pushes(), c.magnitudes());
  }
  return f;
}

FrameWriter::FrameWriter(const fs::path& dir, const Simulation& sim) : dir_(dir / "frames"), series_(sim.world().bodies.size()) {}

void FrameWriter::write(const Simulation& sim, const Recorder& rec, int step) {
  const Scene& sc = sim.scene();
  if (sc.frames_every <= 0) return;
  char num[16];
  std::snprintf(num, sizeof num, "%06d", step);
  const World& w = sim.world();
  const FrameFormat fmt = sc.frame_format;
  const std::string ext = std::string(".") + scene_word(fmt);
  Points force;
  if (fmt != FrameFormat::vtk) force = contact_forces(sim);
  for (std::size_t b = 0; b < w.bodies.size(); ++b) {
    const Body& body = w.bodies[b];
    const int bi = static_cast<int>(b);
    const std::string file = body.name + "_" + num + ext;
    if (fmt == FrameFormat::vtk) {
      write_vtk((dir_ / file).string(), w, bi, "harness " + sc.name + " body " + body.name + " step " + num,
                rec.penetration(bi, step));
      continue;
    }
    FrameData d;
    d.contact_force.assign(force.begin() + body.begin, force.begin() + body.begin + body.n_surface);
    if (rec.sd_step() == step && b < rec.signed_distance().size() && !rec.signed_distance()[b].empty())
      d.signed_distance = &rec.signed_distance()[b];
    d.penetrating = rec.penetration(bi, step);
    write_vtk_xml((dir_ / file).string(), w, bi, d, fmt == FrameFormat::vtu);
    auto& series = series_[b];
    if (series.empty() || series.back().second != xml_escape(file)) series.emplace_back(sim.time(), xml_escape(file));
    write_pvd((dir_ / (body.name + ".pvd")).string(), series);
  }
}

}  // namespace harness
