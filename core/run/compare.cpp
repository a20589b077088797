#include "core/run/compare.hpp"

#include "core/run/summary_keys.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

namespace harness {

namespace fs = std::filesystem;

namespace {

void check_bodies(const std::string& where, const SurfaceState& ref, const World& w) {
  if (ref.bodies.size() != w.bodies.size())
    throw InputError(where, "it has " + std::to_string(ref.bodies.size()) + " bodies, this scene " +
                                std::to_string(w.bodies.size()));
  for (std::size_t b = 0; b < w.bodies.size(); ++b) {
    const int r = ref.body(w.bodies[b].name);
    if (r < 0) throw InputError(where, "it has no body \"" + w.bodies[b].name + "\"");
    if (static_cast<int>(ref.x[r].size()) != w.bodies[b].n_surface)
      throw InputError(where, "body \"" + w.bodies[b].name + "\" has " + std::to_string(ref.x[r].size()) +
                                  " surface nodes there, " + std::to_string(w.bodies[b].n_surface) + " here");
    // A reference with a non-finite node is no reference: said now, not dropped later. Signed
    // distances are measured for a whole body or not at all (every one empty).
    const auto& sd = ref.sd[r];
    const bool measured = std::any_of(sd.begin(), sd.end(), [](double d) { return std::isfinite(d); });
    for (std::size_t i = 0; i < ref.x[r].size(); ++i) {
      if (!ref.x[r][i].allFinite())
        throw InputError(where, "body \"" + w.bodies[b].name + "\" node " + std::to_string(i) + ": position not finite");
      if (measured && !std::isfinite(sd[i]))
        throw InputError(where, "body \"" + w.bodies[b].name + "\" node " + std::to_string(i) +
                                    ": signed distance not finite (the others are measured)");
    }
  }
}

// Reorders the state's bodies to the world's order.
SurfaceState in_world_order(const SurfaceState& s, const World& w) {
  SurfaceState out;
  out.step = s.step;
  out.time = s.time;
  for (const Body& b : w.bodies) {
    const int r = s.body(b.name);
    out.bodies.push_back(b.name);
    out.x.push_back(s.x[r]);
    out.sd.push_back(s.sd[r]);
  }
  return out;
}

}  // namespace

Comparison::Comparison(const std::string& dir, const Simulation& sim, const std::string& option) : dir_(dir) {
  const std::string where = option + " " + dir;
  const fs::path d(dir);
  std::ifstream in(d / "summary.json");
  if (!in) throw InputError(where, "no summary.json (not a finished run or reference)");
  nlohmann::json sum;
  try {
    sum = nlohmann::json::parse(in);
  } catch (const std::exception& e) {
    throw InputError(where, std::string("summary.json is not JSON (") + e.what() + ")");
  }
  const nlohmann::json::json_pointer reference(summary_key::kReference);
  if (sum.contains(reference) && sum[reference].is_object()) {
    is_reference_ = true;
    converged_ = sum.value(nlohmann::json::json_pointer(summary_key::kReferenceConverged), false);
    const nlohmann::json::json_pointer floor(summary_key::kReferenceFloor);
    if (sum.contains(floor) && sum[floor].is_number() && sum[floor].get<double>() > 0.0) floor_ = sum[floor].get<double>();
  }
  const World& w = sim.world();
  const SurfaceState fin = read_surfaces((d / "surfaces.csv").string());
  check_bodies(where, fin, w);
  final_ = in_world_order(fin, w);
  const double dt = sum.value(nlohmann::json::json_pointer(summary_key::kSceneDt), 0.0);
  if (fs::exists(d / "trajectory.bin") && dt == sim.scene().dt)
    for (const SurfaceState& s : read_trajectory((d / "trajectory.bin").string())) {
      check_bodies(where + "/trajectory.bin", s, w);
      steps_.push_back(in_world_order(s, w));
    }
}

const SurfaceState* Comparison::at_step(int step) const {
  const auto it = std::lower_bound(steps_.begin(), steps_.end(), step,
                                   [](const SurfaceState& s, int k) { return s.step < k; });
  return it != steps_.end() && it->step == step ? &*it : nullptr;
}

const SurfaceState& Comparison::target(int step) const {
  const SurfaceState* s = at_step(step);
  return s ? *s : final_;
}

namespace {

bool any_finite(const std::vector<double>& v) {
  return std::any_of(v.begin(), v.end(), [](double d) { return std::isfinite(d); });
}

[[noreturn]] void not_finite(const SurfaceState& s, int b, std::size_t i, const char* what, const char* side) {
  throw ComparisonError("body '" + s.bodies[b] + "' node " + std::to_string(i) + ": " + what + " not finite " + side);
}

}  // namespace

ReferenceErrors Comparison::errors(const SurfaceState& state, const SurfaceState& ref, int host, int guest) {
  ReferenceErrors e;
  double sum2 = 0.0, gap_sum = 0.0;
  long long n = 0;
  e.distances = true;
  for (int b : {host, guest}) e.distances = e.distances && any_finite(state.sd[b]) && any_finite(ref.sd[b]);
  for (int b : {host, guest})
    for (std::size_t i = 0; i < ref.x[b].size(); ++i) {
      const double d = (state.x[b][i] - ref.x[b][i]).norm();
      if (!std::isfinite(d))
        not_finite(state, b, i, "position", state.x[b][i].allFinite() ? "in the reference" : "in this run");
      e.pos_err_max = std::max(e.pos_err_max, d);
      sum2 += d * d;
      ++n;
      if (!e.distances) continue;
      const double sd = state.sd[b][i], sr = ref.sd[b][i];
      if (!std::isfinite(sd)) not_finite(state, b, i, "signed distance", "in this run");
      if (!std::isfinite(sr)) not_finite(state, b, i, "signed distance", "in the reference");
      e.depth_max = std::max(e.depth_max, -sd);
      if (std::fabs(sr) <= kTouchTolerance) {
        ++e.touching;
        const double gap = std::max(0.0, sd - std::max(0.0, sr));
        e.gap_max = std::max(e.gap_max, gap);
        gap_sum += gap;
      }
    }
  e.pos_err_rms = n ? std::sqrt(sum2 / static_cast<double>(n)) : 0.0;
  e.gap_mean = e.touching ? gap_sum / e.touching : 0.0;
  return e;
}

}  // namespace harness
