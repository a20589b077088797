#include "core/run/warnings.hpp"

#include "core/collision/initializer.hpp"

#include <cmath>
#include <algorithm>
#include <cstdio>
#include <tuple>

namespace harness {

namespace {

std::string mm(double m) {
  char b[32];
  std::snprintf(b, sizeof b, "%.3g mm", 1e3 * m);
  return b;
}

double thinnest_extent(const World& w, int body) {
  const Vec3 e = w.bodies[body].rest_max - w.bodies[body].rest_min;
  return e.minCoeff();
}

}  // namespace

std::vector<Warning> start_warnings(const Simulation& sim) {
  std::vector<Warning> out;
  const World& w = sim.world();
  for (std::size_t p = 0; p < sim.pairs().size(); ++p) {
    const Pair& pair = sim.pairs()[p];
    if (!pair.collision) continue;  // no contact simulated: nothing can tunnel through a response
    const std::string key = "contacts." + std::to_string(p);
    const double asked = pair.spec.voxel_size, used = pair.collision->voxel_size();
    if (asked > 0.0 && used > 0.0 && used != asked) {
      char b[160];
      std::snprintf(b, sizeof b, "%.6g m rounded down to a power of two: %.6g m (2^%d)", asked, used,
                    static_cast<int>(std::lround(std::log2(used))));
      out.push_back({key + ".voxel_size", b});
    }
    const int host = pair.spec.host, guest = pair.spec.guest;
    const double hg = rest_surface_edge(w, guest), hh = rest_surface_edge(w, host);
    // The paper's grid lists the host's nodes: a voxel finer than their spacing can hold none of
    // them while a guest node sits inside the host there (voxel_exact lists triangles instead).
    const double hs = host_node_spacing(w, host);
    if (pair.spec.detector == "voxel" && used > 0.0 && hs > used)
      out.push_back({key, "voxel " + mm(used) + " is finer than host '" + w.bodies[host].name + "' node spacing " + mm(hs) +
                              ": a voxel inside the host can hold none of its nodes, guest nodes there go undetected "
                              "(a voxel of at least the spacing, or voxel_exact, avoids it)"});
    if (used > 0.0 && hg > used)
      out.push_back({key, "guest '" + w.bodies[guest].name + "' node spacing " + mm(hg) + " is coarser than the voxel " +
                              mm(used) + ": host nodes can pass between guest nodes undetected (tunnelling expected)"});
    for (const auto& [a, b, h] : {std::tuple<int, int, double>{guest, host, hg}, std::tuple<int, int, double>{host, guest, hh}}) {
      const double t = thinnest_extent(w, b);
      if (h > 0.0 && t > 0.0 && h > t)
        out.push_back({key, "'" + w.bodies[a].name + "' node spacing " + mm(h) + " is coarser than '" + w.bodies[b].name +
                                "' is thick (" + mm(t) + "): one can pass between the other's nodes (tunnelling expected)"});
    }
  }
  return out;
}

}  // namespace harness
