#include "core/run/recorder.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace harness {

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
  for (const Pair& p : pairs)
    for (int body : {p.spec.guest, p.spec.host}) {
      const auto n = static_cast<std::size_t>(w.bodies[body].size());
      open_.emplace_back(n, -1);
      through_last_.emplace_back(n, 0);
      through_start_.emplace_back(n, 0);
    }
  for (const Body& b : w.bodies) pen_flags_.emplace_back(static_cast<std::size_t>(b.size()), 0);
  ke_ = ke_peak_ = sim.kinetic_energy();
  series_.resize(pairs.size());
  initial_energy_ = sim.energy().initial;
  energy_every_ = measurers_.empty() ? kEnergyEvery : std::max(1, sc.references.every);
  energy_.reserve(static_cast<std::size_t>(sc.steps));
  timings_.step.reserve(static_cast<std::size_t>(sc.steps));
  timings_.physics.reserve(static_cast<std::size_t>(sc.steps));
  // The window the run will be judged on if it does not settle first (run_scene.cpp: it runs
  // time.steps, then up to time.settle.max_steps more).
  const int planned_last = sc.steps + (sc.settle.present ? sc.settle.max_steps : 0);
  motion_from_ = window_span(sc, planned_last).from;
  // The time scale: an elastic wave's crossing time of the largest body (window.hpp); the stated
  // length's fallback: a share of the mean rest spring length of the bodies in contact (of all
  // bodies without contact).
  const double dt_crit = sim.stats().stability.dt_crit;
  std::vector<int> contact_bodies;
  for (const Pair& p : pairs) contact_bodies.push_back(p.spec.host), contact_bodies.push_back(p.spec.guest);
  if (contact_bodies.empty())
    for (int b = 0; b < static_cast<int>(w.bodies.size()); ++b) contact_bodies.push_back(b);
  double edge_sum = 0.0;
  for (int b : contact_bodies) edge_sum += rest_spring_length(w, b);
  edge_length_ = contact_bodies.empty() ? 0.0 : edge_sum / static_cast<double>(contact_bodies.size());
  for (int b = 0; b < static_cast<int>(w.bodies.size()); ++b) {
    const Body& body = w.bodies[b];
    Vec3 lo = Vec3::Constant(INFINITY), hi = Vec3::Constant(-INFINITY);
    for (int i = body.begin; i < body.end; ++i) lo = lo.cwiseMin(w.x0[i]), hi = hi.cwiseMax(w.x0[i]);
    const double edge = rest_spring_length(w, b);
    if (std::isfinite(dt_crit) && dt_crit > 0.0 && edge > 0.0 && body.size() > 0)
      time_scale_ = std::max(time_scale_, (hi - lo).maxCoeff() / edge * 0.5 * dt_crit);
  }
  for (int i = 0; i < w.num_nodes(); ++i)
    if (w.is_free(i)) free_mass_ += w.m[i];
}

StabilityInputs Recorder::stability_inputs(const Simulation& sim) const {
  const World& w = sim.world();
  StabilityInputs in;
  in.free_mass = free_mass_;
  in.time_scale = time_scale_ > 0.0 ? time_scale_ : std::numeric_limits<double>::quiet_NaN();
  // The stated length: the largest of the contact's voxel, the reference's floor and the edge share
  // (a motion below a quarter of an edge is below what the mesh resolves, whatever the floor).
  double L = kEdgeShare * edge_length_;
  in.chatter_length_from = "edge share";
  for (const Pair& p : sim.pairs())
    if (p.collision && p.collision->voxel_size() > L) L = p.collision->voxel_size(), in.chatter_length_from = "voxel";
  for (const Comparison* c : {opt_.compare, opt_.compare_also})
    if (c && c->floor() && *c->floor() > L) L = *c->floor(), in.chatter_length_from = "reference floor";
  in.chatter_length = L;
  // The chatter: the largest motion of a node about its mean over the window.
  const int to = sim.step_index();
  const WindowSpan span = window_span(sim.scene(), to);
  if (motion_n_ > 0 && span.from == motion_from_ && !motion_sum_.empty()) {
    double amp = 0.0;
    for (int i = 0; i < w.num_nodes(); ++i) {
      if (!w.is_free(i)) continue;
      const Vec3 mean = motion_sum_[i] / static_cast<double>(motion_n_);
      const Vec3 a = (motion_max_[i] - mean).cwiseMax(mean - motion_min_[i]);
      amp = std::max(amp, a.norm());
    }
    in.chatter_amplitude = amp;
  }
  return in;
}

void Recorder::track(std::size_t p, int role, const std::vector<std::uint8_t>& flags,
                     const std::vector<std::uint8_t>* through, int step, const Simulation& sim) {
  const Pair& pair = sim.pairs()[p];
  const int body = role == 0 ? pair.spec.guest : pair.spec.host;
  const std::size_t k = 2 * p + static_cast<std::size_t>(role);
  std::vector<int>& open = open_[k];
  std::vector<std::uint8_t>& last = through_last_[k];
  std::vector<std::uint8_t>& start = through_start_[k];
  for (std::size_t i = 0; i < flags.size(); ++i) {
    const std::uint8_t thr = through && i < through->size() ? (*through)[i] : 0;
    if (flags[i]) {
      pen_flags_[body][i] = 1;
      if (open[i] < 0) {
        open[i] = static_cast<int>(episodes_.size());
        // Entered since the last measured step: the parity it entered with.
        start[i] = last[i];
        episodes_.push_back({static_cast<int>(p), body, static_cast<int>(i), step, step, true});
      } else {
        episodes_[open[i]].last = step;
      }
    } else if (open[i] >= 0) {
      Episode& e = episodes_[open[i]];
      e.open = false;
      e.tunnelled = thr != start[i];  // left on the other side: gone through, not eliminated
      open[i] = -1;
    } else if (thr != last[i]) {
      // Through (or back) between two measured steps, never found inside: an episode unseen but
      // for its passage.
      episodes_.push_back({static_cast<int>(p), body, static_cast<int>(i), step, step, false, true});
    }
    last[i] = thr;
  }
}

void Recorder::record(const Simulation& sim, bool last) {
  const Scene& sc = sim.scene();
  const int s = sim.step_index();
  measured_now_ = !measurers_.empty() && (s % sc.references.every == 0 || last);
  // The audit's figures (booked in the step's own pass); without it, evaluated here. The stored
  // energies (springs, gravity) on the steps that measure and the last (energy_step): evaluated
  // there, NaN on the others.
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const bool energy_now = last || s % energy_every_ == 0;
  const EnergyLedger& e = energy_now ? sim.energy() : sim.energy_booked();
  ke_ = sim.audited() ? e.kinetic : sim.kinetic_energy();
  ke_peak_ = std::max(ke_peak_, ke_);
  pe_ = !energy_now ? nan : sim.audited() ? e.potential : sim.potential_energy();
  // A peer engine books no work (simulation.hpp): its contact power is unknown, not zero.
  energy_.push_back({sim.engine() ? nan : e.work_contact, sim.engine() ? nan : e.work_external, ke_,
                     energy_now ? e.elastic : nan, sim.residual()});
  timings_.step.push_back(sim.last().step_us);
  timings_.physics.push_back(sim.last().physics_us);
  if (s >= motion_from_ && motion_from_ > 0) {  // the nodes' motion over the planned window
    const World& w = sim.world();
    const auto n = static_cast<std::size_t>(w.num_nodes());
    if (motion_sum_.size() != n) {
      motion_sum_.assign(n, Vec3::Zero());
      motion_min_.assign(n, Vec3::Zero());
      motion_max_.assign(n, Vec3::Zero());
      motion_n_ = 0;
    }
    // Each node relative to its body's mean position (its free nodes'): a body that moves as a
    // whole (in flight after a kick, or through the other body) does not chatter.
    for (const Body& b : w.bodies) {
      Vec3 c = Vec3::Zero();
      int m = 0;
      for (int i = b.begin; i < b.end; ++i)
        if (w.is_free(i)) c += w.x[i], ++m;
      if (m) c /= static_cast<double>(m);
      for (int i = b.begin; i < b.end; ++i) {
        const auto k = static_cast<std::size_t>(i);
        const Vec3 r = w.x[k] - c;
        if (motion_n_ == 0) motion_min_[k] = motion_max_[k] = r;
        motion_sum_[k] += r;
        motion_min_[k] = motion_min_[k].cwiseMin(r);
        motion_max_[k] = motion_max_[k].cwiseMax(r);
      }
    }
    ++motion_n_;
  }
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
    // Exact signed distances where a figure reads them (Measurer::needs); every surface vertex's
    // on the steps that write them all: frames, the trajectory, the last step's surfaces.csv.
    Measurer::DistanceNeeds& needs = measurers_[p]->needs;
    needs = Measurer::DistanceNeeds{};
    needs.all = last || sc.trajectory || (sc.frames_every > 0 && s % sc.frames_every == 0);
    needs.touch = kTouchTolerance;
    if (opt_.compare && !needs.all) {
      const SurfaceState& ref = opt_.compare->target(s);
      const SurfaceState* also = opt_.compare_also ? &opt_.compare_also->target(s) : nullptr;
      const World& w = sim.world();
      ref_sd_world_.resize(w.bodies.size());
      ref_sd_both_.resize(w.bodies.size());
      const auto world_order = [&](const SurfaceState& r, int b, std::vector<double>& out) -> const std::vector<double>* {
        if (static_cast<std::size_t>(b) >= r.sd.size() || r.sd[b].empty()) return nullptr;
        const Body& body = w.bodies[static_cast<std::size_t>(b)];
        if (body.scene_node.empty()) return &r.sd[b];
        out.assign(r.sd[b].size(), 0.0);  // the world's order
        for (int i = 0; i < body.n_surface && static_cast<std::size_t>(i) < out.size(); ++i)
          out[static_cast<std::size_t>(i)] = r.sd[b][static_cast<std::size_t>(body.scene_index(i))];
        return &out;
      };
      const auto body_sd = [&](int b) -> const std::vector<double>* {
        const std::vector<double>* first = world_order(ref, b, ref_sd_world_[static_cast<std::size_t>(b)]);
        if (!also || !first) return first;
        std::vector<double> tmp;
        const std::vector<double>* second = world_order(*also, b, tmp);
        if (!second) return first;
        std::vector<double>& both = ref_sd_both_[static_cast<std::size_t>(b)];
        both = *first;
        for (std::size_t i = 0; i < both.size() && i < second->size(); ++i)
          if (std::abs((*second)[i]) < std::abs(both[i])) both[i] = (*second)[i];
        return &both;
      };
      needs.ref_guest = body_sd(pair.spec.guest);
      needs.ref_host = body_sd(pair.spec.host);
    }
    measurers_[p]->measure(sim.world(), pair.spec, pair.collision ? pair.collision->contacts() : none,
                           pair.collision ? pair.collision->reverse_contacts() : none, m);
    if (m.has_cgal && m.pen_guest && m.pen_host) {
      if (pen_step_ != s)
        for (auto& f : pen_flags_) std::fill(f.begin(), f.end(), 0);
      pen_step_ = s;
      track(p, 0, *m.pen_guest, m.through_guest, s, sim);
      track(p, 1, *m.pen_host, m.through_host, s, sim);
    }
    if (m.has_cgal) {
      t.measured = true;
      t.tp += m.tp;
      t.fp += m.fp;
      t.fn += m.fn;
      t.tp_host += m.tp_host;
      t.fp_host += m.fp_host;
      t.fn_host += m.fn_host;
      t.true_pen_final = m.true_pen_guest + m.true_pen_host;
      t.max_depth_final = m.max_depth;
      t.max_depth_peak = std::max(t.max_depth_peak, m.max_depth);
      timings_.cgal.push_back(m.t_cgal_us);
    }
    if (m.has_fcl) timings_.fcl.push_back(m.t_fcl_us);
  }
  if (measured_now_) pair_figures(sim);
}

TunnelCount Recorder::tunnel_count(std::size_t p) const {
  const Measurement& m = meas_[p];
  return m.has_cgal ? TunnelCount{m.tunnelled_guest, m.tunnelled_host, true} : TunnelCount{};
}

StabilityJudgement Recorder::judge(const Simulation& sim, bool settled) const {
  return judge_stability(sim.scene(), energy_, initial_energy_, settled, stability_inputs(sim));
}

namespace {

// Each body's signed distances from this step's measurements (a body in several pairs: the most
// penetrating); false when no pair measured them.
bool merge_signed_distances(std::vector<std::vector<double>>& sd, const std::vector<Pair>& pairs,
                            const std::vector<Measurement>& meas) {
  bool any = false;
  for (auto& v : sd) v.clear();
  for (std::size_t p = 0; p < pairs.size(); ++p) {
    const Measurement& m = meas[p];
    if (!m.sd_guest || !m.sd_host) continue;
    any = true;
    for (const auto& [body, src] : {std::pair{pairs[p].spec.guest, m.sd_guest}, std::pair{pairs[p].spec.host, m.sd_host}}) {
      std::vector<double>& d = sd[body];
      if (d.empty()) d = *src;
      else
        for (std::size_t i = 0; i < d.size(); ++i) d[i] = std::min(d[i], (*src)[i]);
    }
  }
  return any;
}

// The guest's truly penetrating nodes outside the box [lo, hi] (the grid's region).
int penetrating_outside(const World& w, const Body& g, const std::vector<std::uint8_t>& pen, const Vec3& lo,
                        const Vec3& hi, int& inside_region) {
  int outside = 0;
  inside_region = 0;
  for (int i = 0; i < g.size(); ++i) {
    const Vec3& x = w.x[g.begin + i];
    const bool out = (x.array() < lo.array()).any() || (x.array() > hi.array()).any();
    inside_region += !out;
    if (pen[static_cast<std::size_t>(i)] && out) ++outside;
  }
  return outside;
}

// The signed distance of the guest nodes the contact pushed (a positive magnitude), max and mean,
// into f; `sd_of` a node's signed distance (NaN where there is none).
template <class SignedDistance>
void push_distances(PairStepFigures& f, const Collision& c, const SignedDistance& sd_of) {
  double sum = 0.0;
  int n = 0;
  f.force_dist_max = -std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < c.pushes().size(); ++i) {
    const double d = sd_of(c.pushes()[i].guest);
    if (!(c.magnitudes()[i] > 0.0) || !std::isfinite(d)) continue;
    f.force_dist_max = std::max(f.force_dist_max, d);
    sum += d;
    ++n;
  }
  f.force_dist = n > 0;
  f.force_dist_mean = n ? sum / n : 0.0;
  if (!n) f.force_dist_max = 0.0;
}

}  // namespace

// Signed distances per body from this step's measurements (a body in several pairs: the most
// penetrating), then per pair the signed distance of the nodes its contact pushed, the tunnelled
// nodes, and the error against the reference (its state at this step, or its final state).
void Recorder::pair_figures(const Simulation& sim) {
  const World& w = sim.world();
  const auto& pairs = sim.pairs();
  const int step = sim.step_index();
  const bool any = merge_signed_distances(sd_, pairs, meas_);
  if (any) sd_step_ = step;
  auto sd_of = [&](int node) {
    for (std::size_t b = 0; b < w.bodies.size(); ++b) {
      const Body& body = w.bodies[b];
      if (node >= body.begin && node < body.begin + body.n_surface && !sd_[b].empty()) return sd_[b][node - body.begin];
    }
    return std::numeric_limits<double>::quiet_NaN();  // an interior node: no signed distance
  };
  const SurfaceState now = opt_.compare && any ? surface_state(w, step, sim.time(), sd_) : SurfaceState{};
  for (std::size_t p = 0; p < pairs.size(); ++p) {
    PairStepFigures& f = figures_[p];
    PairSeries& ser = series_[p];
    const Measurement& m = meas_[p];
    f = PairStepFigures{};
    f.tunnelled = tunnel_count(p);
    PairTotals& t = totals_[p];
    if (f.tunnelled.measured) {
      ser.tunnelled.add(step, f.tunnelled.guest + f.tunnelled.host);
      t.tunnelled_guest_peak = std::max(t.tunnelled_guest_peak, f.tunnelled.guest);
      t.tunnelled_host_peak = std::max(t.tunnelled_host_peak, f.tunnelled.host);
    }
    if (m.has_cgal) {
      ser.depth_max.add(step, m.max_depth);
      ser.true_pen.add(step, m.true_pen_guest + m.true_pen_host);
      ser.true_pen_guest.add(step, m.true_pen_guest);
      Vec3 lo, hi;
      const Collision* c = pairs[p].collision.get();
      if (c && m.pen_guest && c->detector().region(lo, hi)) {
        int in_region = 0;
        const int outside = penetrating_outside(w, w.bodies[pairs[p].spec.guest], *m.pen_guest, lo, hi, in_region);
        ser.outside_region.add(step, outside);
        t.has_region = true;
        t.outside_region_final = outside;
        t.outside_region_peak = std::max(t.outside_region_peak, outside);
        const double v = c->voxel_size();
        long long voxels = 1;
        for (int k = 0; k < 3; ++k) voxels *= std::llround((hi[k] - lo[k]) / v);
        t.region_voxels_final = voxels;
        t.region_voxels_peak = std::max(t.region_voxels_peak, voxels);
        t.region_voxels_sum += static_cast<double>(voxels);
        ++t.region_samples;
        t.region_guest_sum += in_region;
        t.region_pen_sum += m.true_pen_guest - outside;
      }
    }
    if (!any) continue;
    if (const Collision* c = pairs[p].collision.get()) push_distances(f, *c, sd_of);
    if (opt_.compare) {
      f.vs_reference = true;
      f.errors = Comparison::errors(now, opt_.compare->target(step), pairs[p].spec.host, pairs[p].spec.guest);
      if (m.has_cgal) f.errors.depth_max = std::max(f.errors.depth_max, m.max_depth);  // interior nodes too
      ser.pos_err_max.add(step, f.errors.pos_err_max);
      ser.pos_err_rms.add(step, f.errors.pos_err_rms);
      if (f.errors.distances) {
        ser.gap_max.add(step, f.errors.gap_max);
        ser.gap_mean.add(step, f.errors.gap_mean);
      }
      if (opt_.compare_also) {
        f.vs_also = true;
        const ReferenceErrors& e = f.also_errors =
            Comparison::errors(now, opt_.compare_also->target(step), pairs[p].spec.host, pairs[p].spec.guest);
        ser.also_pos_err_max.add(step, e.pos_err_max);
        ser.also_pos_err_rms.add(step, e.pos_err_rms);
        if (e.distances) {
          ser.also_gap_max.add(step, e.gap_max);
          ser.also_gap_mean.add(step, e.gap_mean);
        }
      }
    }
  }
}

std::vector<ReferenceErrors> Recorder::final_errors(const Simulation& sim) const {
  if (!opt_.compare) return {};
  return final_errors_vs(sim, *opt_.compare);
}

std::vector<ReferenceErrors> Recorder::final_errors_also(const Simulation& sim) const {
  if (!opt_.compare || !opt_.compare_also) return {};
  return final_errors_vs(sim, *opt_.compare_also);
}

std::vector<ReferenceErrors> Recorder::final_errors_vs(const Simulation& sim, const Comparison& cmp) const {
  std::vector<ReferenceErrors> out;
  const bool measured = sd_step_ == sim.step_index();
  const SurfaceState now = surface_state(sim.world(), sim.step_index(), sim.time(), measured ? sd_ : std::vector<std::vector<double>>{});
  for (std::size_t p = 0; p < sim.pairs().size(); ++p) {
    const Pair& pair = sim.pairs()[p];
    ReferenceErrors e = Comparison::errors(now, cmp.final_state(), pair.spec.host, pair.spec.guest);
    if (measured && meas_[p].has_cgal) e.depth_max = std::max(e.depth_max, meas_[p].max_depth);
    out.push_back(e);
  }
  return out;
}

const std::vector<std::uint8_t>* Recorder::penetration(int body, int step) const {
  return pen_step_ == step ? &pen_flags_[body] : nullptr;
}

}  // namespace harness
