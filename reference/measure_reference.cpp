#include "reference/measure_reference.hpp"

#include "reference/cgal_constructions.hpp"

#include "core/clock.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

namespace harness {

namespace {

void check_pair(const World& w, const ContactSpec& pair) {
  const int n = static_cast<int>(w.bodies.size());
  if (pair.host < 0 || pair.host >= n || pair.guest < 0 || pair.guest >= n || pair.host == pair.guest)
    throw std::invalid_argument("reference measurer: host and guest must be two distinct bodies");
}

// Nodes [begin, end) of one body against the other body's surface: count the strictly inside
// ones, add their distances to the surface into the depth sums, flag them when `flags` is given;
// and the signed distance of every surface vertex (negative inside) into `sd` (n_surface).
// A surface vertex outside the other body's bounding box by more than a quarter of that box's
// diagonal gets its distance to the box instead (a lower bound, itself above that quarter): the
// exact search from far away visits much of the tree and was most of the measurement's time,
// while every figure that reads these distances (depth of inside nodes, the gap of nodes the
// reference has touching, the distance of pushed nodes) needs them exact only near the other body;
// a gap beyond the quarter diagonal is reported as that lower bound, still far above any tolerance.
// hints (n_surface): each surface vertex's closest face at its previous measurement, in and out;
// it seeds the exact search with the point of that face nearest the vertex (an upper bound, so the
// answer is the same, and no kd-tree to rebuild after each update).
// need (n_surface, or null for all): the surface vertices whose distance must be exact when they
// are outside; the others get their distance to the other body's box (a lower bound, 0 within it).
int classify(const World& w, const Body& b, const CgalSurface& other, double& max_depth,
             double& sum_depth, std::uint8_t* flags, double* sd, int* hints, const std::uint8_t* need = nullptr) {
  Vec3 lo, hi;
  other.bounds(lo, hi);
  const double far = 0.25 * (hi - lo).norm();
  int count = 0;
  for (int i = b.begin; i < b.end; ++i) {
    const Vec3& x = w.x[i];
    const double box = (lo - x).cwiseMax(x - hi).cwiseMax(0.0).norm();
    const bool in = box == 0.0 && other.strictly_inside(x);
    if (flags) flags[i - b.begin] = in ? 1 : 0;
    const bool surface = i - b.begin < b.n_surface;
    if (!in && !surface) continue;
    double d;
    if (!in && (box > far || (need && !need[i - b.begin]))) {
      d = box;
    } else if (surface) {
      Vec3 q;
      int& h = hints[i - b.begin];
      h = other.closest_face(x, &q, h);
      d = (q - x).norm();
    } else {
      d = std::sqrt(other.squared_distance(x));
    }
    if (surface) sd[i - b.begin] = in ? -d : d;
    if (!in) continue;
    ++count;
    max_depth = std::max(max_depth, d);
    sum_depth += d;
  }
  return count;
}

// The surface vertices of b whose distance must be exact (Measurer::needs): those a detector
// reported (global node indices) and those within `touch` of the other body in the reference.
void mark_needs(std::vector<std::uint8_t>& need, const Body& b, const std::vector<double>* ref, double touch,
                   const std::vector<Contact>& detected) {
  need.assign(static_cast<std::size_t>(b.n_surface), 0);
  if (ref)
    for (std::size_t i = 0; i < need.size() && i < ref->size(); ++i) need[i] = std::fabs((*ref)[i]) <= touch ? 1 : 0;
  for (const Contact& c : detected) {
    const int li = c.guest - b.begin;
    if (li >= 0 && li < b.n_surface) need[static_cast<std::size_t>(li)] = 1;
  }
}

bool all_finite(const World& w, const Body& b) {
  for (int i = b.begin; i < b.end; ++i)
    if (!w.x[i].allFinite()) return false;
  return true;
}

}  // namespace

int Passages::update(const World& w, const Body& b, const CgalSurface& other, const std::vector<std::uint8_t>& pen) {
  const std::size_t n = static_cast<std::size_t>(b.size());
  auto nearest_normal = [&](const Vec3& x) { return other.face_normal(other.closest_face(x)); };
  if (!started) {
    prev.assign(n, Vec3::Zero());
    inside.assign(n, 0);
    entry.assign(n, Vec3::Zero());
    through.assign(n, 0);
    for (std::size_t i = 0; i < n; ++i) {
      prev[i] = w.x[b.begin + static_cast<int>(i)];
      inside[i] = pen[i];
      if (pen[i]) entry[i] = nearest_normal(prev[i]);
    }
    started = true;
    return 0;
  }
  Vec3 lo, hi;
  other.bounds(lo, hi);
  int count = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3& x = w.x[b.begin + static_cast<int>(i)];
    const Vec3& a = prev[i];
    bool state = inside[i] != 0;
    Vec3 n_in = entry[i];
    // Only a path whose box meets the other body's box can cross it.
    if ((a.cwiseMin(x).array() <= hi.array()).all() && (a.cwiseMax(x).array() >= lo.array()).all())
      other.crossings(a, x, hits_);
    else
      hits_.clear();
    for (const SurfaceCrossing& c : hits_) {
      if (state) {
        if (n_in.dot(c.normal) < 0.0) through[i] ^= 1;
      } else {
        n_in = c.normal;
      }
      state = !state;
    }
    // A crossing missed or counted twice (a path grazing an edge, a collapsed face): the exact
    // side decides, with the face nearest to where the node is now.
    const bool in_now = pen[i] != 0;
    if (state != in_now) {
      const Vec3 nn = nearest_normal(x);
      if (in_now) n_in = nn;
      else if (n_in.dot(nn) < 0.0) through[i] ^= 1;
    }
    entry[i] = in_now ? n_in : Vec3::Zero();
    inside[i] = pen[i];
    prev[i] = x;
    count += through[i];
  }
  return count;
}

ReferenceMeasurer::ReferenceMeasurer(const World& w, const ContactSpec& pair,
                                     const ReferenceSpec& spec, FclBv bv, FclRefitPolicy refit)
    : spec_(spec), host_(pair.host), guest_(pair.guest), fc_host_(bv, refit), fc_guest_(bv, refit) {
  check_pair(w, pair);
  const Body& H = w.bodies[host_];
  const Body& G = w.bodies[guest_];
  if (spec_.cgal || spec_.volume) {
    cg_host_.set_topology(H.n_surface, H.faces);
    cg_guest_.set_topology(G.n_surface, G.faces);
    pen_guest_.assign(G.size(), 0);
    pen_host_.assign(H.size(), 0);
    sd_guest_.assign(G.n_surface, 0.0);
    sd_host_.assign(H.n_surface, 0.0);
    hint_guest_.assign(G.n_surface, -1);
    hint_host_.assign(H.n_surface, -1);
    seen_.assign(G.size(), 0);
    seen_host_.assign(H.size(), 0);
  }
  // Passages are followed from the state the measurer is made on (the run's first), not from its
  // first measured step: a node that passes through before that step counts too.
  if (spec_.cgal && all_finite(w, H) && all_finite(w, G)) {
    cg_host_.update(&w.x[H.begin]);
    cg_guest_.update(&w.x[G.begin]);
    double max_depth = 0.0, sum_depth = 0.0;
    classify(w, G, cg_host_, max_depth, sum_depth, pen_guest_.data(), sd_guest_.data(), hint_guest_.data());
    classify(w, H, cg_guest_, max_depth, sum_depth, pen_host_.data(), sd_host_.data(), hint_host_.data());
    pass_guest_.update(w, G, cg_host_, pen_guest_);
    pass_host_.update(w, H, cg_guest_, pen_host_);
  }
  if (spec_.fcl) {
    fc_host_.set_topology(H.n_surface, H.faces);
    fc_guest_.set_topology(G.n_surface, G.faces);
  }
}

void ReferenceMeasurer::measure(const World& w, const ContactSpec& pair, const std::vector<Contact>& detected,
                                const std::vector<Contact>& detected_host, Measurement& out) {
  if (pair.host != host_ || pair.guest != guest_)
    throw std::invalid_argument("reference measurer: called for another pair than it was made for");
  out = Measurement{};
  // Exact predicates on a NaN abort inside GMP: a diverged state is not measured (has_* false).
  if (!all_finite(w, w.bodies[host_]) || !all_finite(w, w.bodies[guest_])) return;
  if (spec_.cgal || spec_.volume) {
    const auto t0 = Clock::now();  // CGAL's time includes its surfaces' update
    cg_host_.update(&w.x[w.bodies[host_].begin]);
    cg_guest_.update(&w.x[w.bodies[guest_].begin]);
    if (spec_.cgal) measure_cgal(w, t0, detected, detected_host, out);
    if (spec_.volume) {
      const auto t1 = Clock::now();
      out.has_volume = intersection_volume(cg_guest_, cg_host_, out.penetration_volume);
      out.t_volume_us = us_since(t1);
    }
  }
  if (spec_.fcl) measure_fcl(w, out);
  if (spec_.ccd) measure_ccd(w, out);
}

void ReferenceMeasurer::measure_cgal(const World& w, Clock::time_point t0, const std::vector<Contact>& detected,
                                     const std::vector<Contact>& detected_host, Measurement& out) {
  const Body& H = w.bodies[host_];
  const Body& G = w.bodies[guest_];
  double max_depth = 0.0, sum_depth = 0.0;
  const bool some = !needs.all;
  if (some) {
    mark_needs(need_guest_, G, needs.ref_guest, needs.touch, detected);
    mark_needs(need_host_, H, needs.ref_host, needs.touch, detected_host);
  }
  out.true_pen_guest = classify(w, G, cg_host_, max_depth, sum_depth, pen_guest_.data(), sd_guest_.data(),
                                hint_guest_.data(), some ? need_guest_.data() : nullptr);
  out.true_pen_host = classify(w, H, cg_guest_, max_depth, sum_depth, pen_host_.data(), sd_host_.data(),
                               hint_host_.data(), some ? need_host_.data() : nullptr);
  out.tunnelled_guest = pass_guest_.update(w, G, cg_host_, pen_guest_);
  out.tunnelled_host = pass_host_.update(w, H, cg_guest_, pen_host_);
  out.pen_guest = &pen_guest_;
  out.pen_host = &pen_host_;
  out.sd_guest = &sd_guest_;
  out.sd_host = &sd_host_;
  out.through_guest = &pass_guest_.through;
  out.through_host = &pass_host_.through;
  const int n_pen = out.true_pen_guest + out.true_pen_host;
  out.max_depth = max_depth;
  out.mean_depth = n_pen > 0 ? sum_depth / n_pen : 0.0;
  score_detected(w, detected, detected_host, out);
  out.surfaces_intersect = surfaces_intersect(cg_guest_, cg_host_, /*bounded_sides=*/true);
  out.has_cgal = true;
  out.t_cgal_us = us_since(t0);
}

// The detector's reports against the truly penetrating nodes: each node once, however often it
// was reported; a node outside its body is a false report.
void ReferenceMeasurer::score_detected(const World& w, const std::vector<Contact>& detected,
                                       const std::vector<Contact>& detected_host, Measurement& out) {
  if (++stamp_ == 0) {
    std::fill(seen_.begin(), seen_.end(), 0);
    std::fill(seen_host_.begin(), seen_host_.end(), 0);
    stamp_ = 1;
  }
  auto score = [&](const std::vector<Contact>& found, const Body& b, std::vector<int>& seen,
                   const std::vector<std::uint8_t>& pen, int& tp, int& fp) {
    for (const Contact& c : found) {
      const int li = c.guest - b.begin;  // the node looked up (a host node the other way round)
      if (li < 0 || li >= b.size()) {
        ++fp;
        continue;
      }
      if (seen[li] == stamp_) continue;
      seen[li] = stamp_;
      if (pen[li]) ++tp;
      else ++fp;
    }
  };
  score(detected, w.bodies[guest_], seen_, pen_guest_, out.tp, out.fp);
  score(detected_host, w.bodies[host_], seen_host_, pen_host_, out.tp_host, out.fp_host);
  out.fn = out.true_pen_guest - out.tp;
  out.fn_host = out.true_pen_host - out.tp_host;
}

void ReferenceMeasurer::measure_fcl(const World& w, Measurement& out) {
  const auto t0 = Clock::now();
  fc_host_.update(&w.x[w.bodies[host_].begin]);
  fc_guest_.update(&w.x[w.bodies[guest_].begin]);
  intersecting_pairs(fc_guest_, fc_host_, pairs_, /*with_depth=*/true);
  out.fcl_pairs = static_cast<int>(pairs_.size());
  for (const TrianglePair& p : pairs_)
    if (p.has_depth) out.fcl_max_depth = std::max(out.fcl_max_depth, p.depth);
  out.has_fcl = true;
  out.t_fcl_us = us_since(t0);
}

void ReferenceMeasurer::measure_ccd(const World& w, Measurement& out) {
  const auto t0 = Clock::now();
  const Body& H = w.bodies[host_];
  const Body& G = w.bodies[guest_];
  const bool hulls = convex_hull(&w.x[G.begin], G.size(), hull_v_[0], hull_f_[0]) &&
                     convex_hull(&w.x[H.begin], H.size(), hull_v_[1], hull_f_[1]);
  out.has_ccd = hulls && convex_signed_distance(hull_v_[0], hull_f_[0], hull_v_[1], hull_f_[1], out.ccd_distance);
  out.t_ccd_us = us_since(t0);
}

std::unique_ptr<Measurer> make_reference_measurer(const World& w, const ContactSpec& pair,
                                                  const ReferenceSpec& spec) {
  return std::make_unique<ReferenceMeasurer>(w, pair, spec);
}

std::string reference_versions() { return "FCL " + fcl_version() + ", CGAL " + cgal_version(); }

std::map<std::string, std::string> reference_version_map() {
  return {{"FCL", fcl_version()}, {"CGAL", cgal_version()}};
}

}  // namespace harness
