#include "core/run/recorder.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace harness {

Vec3 approach_axis(const World& w, const ContactSpec& pair) {
  Vec3 hl, hh, gl, gh;
  body_bounds(w, pair.host, hl, hh);
  body_bounds(w, pair.guest, gl, gh);
  Vec3 a = 0.5 * (gl + gh) - 0.5 * (hl + hh);
  const double n = a.norm();
  return n > 0.0 && std::isfinite(n) ? Vec3(a / n) : Vec3(Vec3::UnitZ());
}

int tunnelled_nodes(const World& w, const ContactSpec& pair, const Vec3& axis) {
  const Body& H = w.bodies[pair.host];
  const Body& G = w.bodies[pair.guest];
  double lo = std::numeric_limits<double>::infinity();
  for (int i = H.begin; i < H.end; ++i) lo = std::min(lo, w.x[i].dot(axis));
  int n = 0;
  for (int i = G.begin; i < G.end; ++i)
    if (w.x[i].dot(axis) < lo) ++n;
  return n;
}

Recorder::Recorder(const Simulation& sim, const RecorderOptions& options) : opt_(options) {
  const Scene& sc = sim.scene();
  const World& w = sim.world();
  const auto& pairs = sim.pairs();
  if (sc.references.cgal || sc.references.fcl || sc.references.ccd) {
    if (!opt_.measurer) throw InputError(sc.file + ": references.solvers", "this build has no reference solvers");
    for (const Pair& p : pairs) measurers_.push_back(opt_.measurer(w, p.spec, sc.references));
  }
  meas_.resize(pairs.size());
  figures_.resize(pairs.size());
  sd_.resize(w.bodies.size());
  totals_.resize(pairs.size());
  for (const Pair& p : pairs) {
    open_.emplace_back(static_cast<std::size_t>(w.bodies[p.spec.guest].size()), -1);
    open_.emplace_back(static_cast<std::size_t>(w.bodies[p.spec.host].size()), -1);
    axes_.push_back(approach_axis(w, p.spec));
  }
  for (const Body& b : w.bodies) pen_flags_.emplace_back(static_cast<std::size_t>(b.size()), 0);
  ke_ = ke_peak_ = sim.kinetic_energy();
  timings_.step.reserve(static_cast<std::size_t>(sc.steps));
  timings_.physics.reserve(static_cast<std::size_t>(sc.steps));
}

void Recorder::track(std::size_t p, int role, const std::vector<std::uint8_t>& flags, int step, const Simulation& sim) {
  const Pair& pair = sim.pairs()[p];
  const int body = role == 0 ? pair.spec.guest : pair.spec.host;
  std::vector<int>& open = open_[2 * p + static_cast<std::size_t>(role)];
  for (std::size_t i = 0; i < flags.size(); ++i) {
    if (flags[i]) {
      pen_flags_[body][i] = 1;
      if (open[i] < 0) {
        open[i] = static_cast<int>(episodes_.size());
        episodes_.push_back({static_cast<int>(p), body, static_cast<int>(i), step, step, true});
      } else {
        episodes_[open[i]].last = step;
      }
    } else if (open[i] >= 0) {
      episodes_[open[i]].open = false;
      open[i] = -1;
    }
  }
}

void Recorder::record(const Simulation& sim, bool last) {
  const Scene& sc = sim.scene();
  const int s = sim.step_index();
  measured_now_ = !measurers_.empty() && (s % sc.references.every == 0 || last);
  ke_ = sim.kinetic_energy();
  ke_peak_ = std::max(ke_peak_, ke_);
  pe_ = sim.potential_energy();
  timings_.step.push_back(sim.last().step_us);
  timings_.physics.push_back(sim.last().physics_us);
  if (!sim.pairs().empty() && sc.has(kContact)) {
    timings_.detect.push_back(sim.last().detect_us);
    timings_.eliminate.push_back(sim.last().eliminate_us);
  }
  for (std::size_t p = 0; p < sim.pairs().size(); ++p) {
    const Pair& pair = sim.pairs()[p];
    PairTotals& t = totals_[p];
    t.contacts_total += pair.last.contacts;
    if (pair.last.beyond_band >= 0) {
      t.has_band = true;
      t.beyond_band_total += pair.last.beyond_band;
      t.beyond_band_peak = std::max(t.beyond_band_peak, pair.last.beyond_band);
    }
    if (!measured_now_) continue;
    static const std::vector<Contact> none;
    Measurement& m = meas_[p];
    m = Measurement{};
    measurers_[p]->measure(sim.world(), pair.spec, pair.collision ? pair.collision->contacts() : none, m);
    if (m.has_cgal && m.pen_guest && m.pen_host) {
      if (pen_step_ != s)
        for (auto& f : pen_flags_) std::fill(f.begin(), f.end(), 0);
      pen_step_ = s;
      track(p, 0, *m.pen_guest, s, sim);
      track(p, 1, *m.pen_host, s, sim);
    }
    if (m.has_cgal) {
      t.measured = true;
      t.tp += m.tp;
      t.fp += m.fp;
      t.fn += m.fn;
      t.true_pen_final = m.true_pen_guest + m.true_pen_host;
      t.max_depth_final = m.max_depth;
      t.max_depth_peak = std::max(t.max_depth_peak, m.max_depth);
      timings_.cgal.push_back(m.t_cgal_us);
    }
    if (m.has_fcl) timings_.fcl.push_back(m.t_fcl_us);
  }
  if (measured_now_) pair_figures(sim);
}

// Signed distances per body from this step's measurements (a body in several pairs: the most
// penetrating), then per pair the signed distance of the nodes its contact pushed, and the error
// against the reference's state at this step.
void Recorder::pair_figures(const Simulation& sim) {
  const World& w = sim.world();
  const auto& pairs = sim.pairs();
  bool any = false;
  for (auto& v : sd_) v.clear();
  for (std::size_t p = 0; p < pairs.size(); ++p) {
    const Measurement& m = meas_[p];
    if (!m.sd_guest || !m.sd_host) continue;
    any = true;
    for (const auto& [body, src] : {std::pair{pairs[p].spec.guest, m.sd_guest}, std::pair{pairs[p].spec.host, m.sd_host}}) {
      std::vector<double>& d = sd_[body];
      if (d.empty()) d = *src;
      else
        for (std::size_t i = 0; i < d.size(); ++i) d[i] = std::min(d[i], (*src)[i]);
    }
  }
  if (!any) return;
  sd_step_ = sim.step_index();
  auto sd_of = [&](int node) {
    for (std::size_t b = 0; b < w.bodies.size(); ++b) {
      const Body& body = w.bodies[b];
      if (node >= body.begin && node < body.begin + body.n_surface && !sd_[b].empty()) return sd_[b][node - body.begin];
    }
    return std::numeric_limits<double>::quiet_NaN();  // an interior node: no signed distance
  };
  const SurfaceState* ref = opt_.compare ? opt_.compare->at_step(sim.step_index()) : nullptr;
  const SurfaceState now = ref ? surface_state(w, sim.step_index(), sim.time(), sd_) : SurfaceState{};
  for (std::size_t p = 0; p < pairs.size(); ++p) {
    PairStepFigures& f = figures_[p];
    f = PairStepFigures{};
    if (const Collision* c = pairs[p].collision.get()) {
      double sum = 0.0;
      int n = 0;
      f.force_dist_max = -std::numeric_limits<double>::infinity();
      for (std::size_t i = 0; i < c->pushes().size(); ++i) {
        const double d = sd_of(c->pushes()[i].guest);
        if (!(c->magnitudes()[i] > 0.0) || !std::isfinite(d)) continue;
        f.force_dist_max = std::max(f.force_dist_max, d);
        sum += d;
        ++n;
      }
      f.force_dist = n > 0;
      f.force_dist_mean = n ? sum / n : 0.0;
      if (!n) f.force_dist_max = 0.0;
    }
    if (ref) {
      f.vs_reference = true;
      f.errors = Comparison::errors(now, *ref, pairs[p].spec.host, pairs[p].spec.guest);
    }
  }
}

std::vector<ReferenceErrors> Recorder::final_errors(const Simulation& sim) const {
  std::vector<ReferenceErrors> out;
  if (!opt_.compare) return out;
  const SurfaceState now = surface_state(sim.world(), sim.step_index(), sim.time(), sd_);
  for (const Pair& p : sim.pairs())
    out.push_back(Comparison::errors(now, opt_.compare->final_state(), p.spec.host, p.spec.guest));
  return out;
}

const std::vector<std::uint8_t>* Recorder::penetration(int body, int step) const {
  return pen_step_ == step ? &pen_flags_[body] : nullptr;
}

int Recorder::tunnelled(const Simulation& sim, std::size_t p) const {
  return tunnelled_nodes(sim.world(), sim.pairs()[p].spec, axes_[p]);
}

}  // namespace harness
