#include "core/collision/collision.hpp"

#include "core/clock.hpp"
#include "core/collision/responses/force_rule.hpp"
#include "core/collision/responses/force_rules.hpp"
#include "core/collision/responses/projection.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

namespace harness {

void check_pair(const World& w, const ContactSpec& spec) {
  if (spec.made != kContactSpecMade)
    throw std::logic_error("contact pair: a ContactSpec not made from the scene's key table (use the scene loader or "
                           "contact_spec_defaults(), then set its fields)");
  const int nb = static_cast<int>(w.bodies.size());
  if (spec.host < 0 || spec.host >= nb || spec.guest < 0 || spec.guest >= nb)
    throw std::invalid_argument("contact pair: host or guest body index out of range");
  if (spec.host == spec.guest) throw std::invalid_argument("contact pair: host and guest must be different bodies");
}

Collision::Collision(const World& w, ContactSpec spec, ExactDetectorMaker exact) : spec_(std::move(spec)) {
  check_pair(w, spec_);
  rule_ = find_force_rule(spec_.force_rule);
  if (!rule_) throw std::invalid_argument("contact pair: no force rule \"" + spec_.force_rule + "\"");
  if (spec_.force_parameters.size() != rule_->parameters.size())
    throw std::invalid_argument("contact pair: force rule \"" + spec_.force_rule + "\" takes " +
                                std::to_string(rule_->parameters.size()) + " parameters (set_force_rule)");
  for (std::size_t i = 0; i < rule_->parameters.size(); ++i) {
    const RuleParameter& p = rule_->parameters[i];
    const double v = spec_.force_parameters[i];
    if (!std::isfinite(v) || v < p.lo || v > p.hi)
      throw std::invalid_argument(std::string("contact pair: ") + p.name + " must be finite and within " +
                                  std::to_string(p.lo) + " to " + std::to_string(p.hi));
  }
  elim_ = find_eliminator(spec_.eliminator);
  if (!elim_) throw std::invalid_argument("contact pair: no eliminator \"" + spec_.eliminator + "\"");
  if (*elim_->detector && std::string(elim_->detector) != spec_.detector)
    throw std::invalid_argument("eliminator \"" + spec_.eliminator + "\" needs detector \"" + elim_->detector +
                                "\" (its detection gives the pushes)");
  detector_ = make_detector(spec_.detector, exact);
  eliminator_ = make_eliminator(spec_.eliminator);
  detector_->initialize(w, spec_);
  contacts_.reserve(static_cast<std::size_t>(w.bodies[spec_.guest].size()));
  magnitude_.reserve(contacts_.capacity());
  pushes_.reserve(contacts_.capacity());
  share_.assign(w.x.size(), 0);
  // Length scale of the automatic force for detectors without a grid: the host's node spacing.
  length_scale_ = rest_spring_length(w, spec_.host);
  if (volume()) volume_pixel_ = volume_pixel(w, spec_.host, spec_.guest, spec_.volume_pixel);
  if (spec_.two_sided) {
    reverse_spec_ = spec_;
    std::swap(reverse_spec_.host, reverse_spec_.guest);
    reverse_ = make_detector(spec_.detector, exact);
    reverse_->initialize(w, reverse_spec_);
    reverse_contacts_.reserve(static_cast<std::size_t>(w.bodies[spec_.host].size()));
    const std::size_t all = contacts_.capacity() + reverse_contacts_.capacity();
    pushes_.reserve(all);
    magnitude_.reserve(all);
    reverse_pushes_.reserve(reverse_contacts_.capacity());
  }
}

int Collision::detect(const World& w) {
  detector_->detect(w, contacts_);
  return static_cast<int>(contacts_.size());
}

void Collision::detect_all(const World& w) {
  detector_->detect(w, contacts_);
  if (reverse_) reverse_->detect(w, reverse_contacts_);
}

void Collision::all_pushes(const World& w) {
  eliminator_->pushes(w, spec_, *detector_, contacts_, pushes_);
  if (reverse_) {  // the other way round's pushes after this way's
    eliminator_->pushes(w, reverse_spec_, *reverse_, reverse_contacts_, reverse_pushes_);
    pushes_.insert(pushes_.end(), reverse_pushes_.begin(), reverse_pushes_.end());
  }
}

void Collision::detect_ahead(const World& w, int part) {
  const auto t0 = Clock::now();
  if (part == 0) detector_->detect(w, contacts_);
  else reverse_->detect(w, reverse_contacts_);
  ahead_us_[part] = us_since(t0);
}

PairStep Collision::finish(PairStep s, double detect_us, Clock::time_point t1) {
  stepped_ = true;
  const auto t2 = Clock::now();
  s.contacts = static_cast<int>(contacts_.size() + reverse_contacts_.size());
  s.beyond_band = detector_->beyond_band();
  if (reverse_ && s.beyond_band >= 0) s.beyond_band += std::max(0, reverse_->beyond_band());
  s.detect_us = detect_us;
  s.eliminate_us = us_between(t1, t2);
  return s;
}

PairStep Collision::project(World& w, double h) {
  PairStep s;
  projected_h_ = h;
  const auto t0 = Clock::now();
  detect_all(w);
  const auto t1 = Clock::now();
  if (volume()) {  // the bound and the restriction (responses/volume.hpp)
    pushes_.clear();
    magnitude_.clear();
    s.force = restrict_volume(w, spec_.host, spec_.guest, volume_pixel_, h, volume_step_, spec_.invert_push);
    return finish(s, us_between(t0, t1), t1);
  }
  all_pushes(w);
  if (spec_.invert_push)
    for (Push& p : pushes_) p.normal = -p.normal;
  magnitude_.assign(pushes_.size(), 0.0);
  s.force = project_pushes(w, pushes_, h);
  for (std::size_t i = 0; i < pushes_.size(); ++i) magnitude_[i] = pushes_[i].depth > 0.0 ? 1.0 : 0.0;
  return finish(s, us_between(t0, t1), t1);
}

void Collision::set_response(OwnResponse r) {
  if (r.force && projects())
    throw std::invalid_argument("a response of its own needs a force eliminator (line, plane), not a projection");
  response_ = std::move(r.force);
  response_name_ = response_ ? std::move(r.name) : std::string();
  // The eliminator gives a response what it gives the penalty rule, whatever the scene's force
  // rule: each push's contact normal and depth (penalty_depth), which the other rules do not need.
  if (response_) {
    set_force_rule(spec_, kDefaultObjectRule, {{"stiffness", 0.0}});
    rule_ = &force_rule_of(spec_);
    if (reverse_) reverse_spec_.force_rule = spec_.force_rule, reverse_spec_.force_parameters = spec_.force_parameters;
  }
}

PairStep Collision::step(World& w, double h) {
  PairStep s;
  if (projects()) return s;
  double detect_us = ahead_us_[0] + ahead_us_[1];
  if (!ahead_) {
    const auto t0 = Clock::now();
    detect_all(w);
    detect_us = us_since(t0);
  }
  ahead_ = false;
  const auto t1 = Clock::now();
  all_pushes(w);
  if (response_) {  // the program's response: its forces per node; magnitude per contact, the guest's |f|
    for (Push& p : pushes_) p.n = spec_.invert_push ? -p.normal : p.normal;  // the direction it is given
    response_f_.assign(w.x.size(), Vec3::Zero());
    response_(w, pushes_, h, response_f_);
    if (response_f_.size() != w.x.size()) throw std::runtime_error("contact response: forces for every node expected");
    magnitude_.resize(pushes_.size());
    for (std::size_t i = 0; i < pushes_.size(); ++i) {
      magnitude_[i] = response_f_[pushes_[i].guest].norm();
      s.force = std::max(s.force, magnitude_[i]);
    }
    for (std::size_t i = 0; i < w.x.size(); ++i) w.f[i] += response_f_[i];
    return finish(s, detect_us, t1);
  }
  {
    RuleStep rs{w, pushes_, h, length(), spec_, share_};
    s.force = rule_->force(rs, spec_.force_parameters, magnitude_);
  }
  if (spec_.damping > 0.0) s.force = damp_contact_forces(w, pushes_, spec_.damping, magnitude_);
  if (spec_.invert_push)
    for (Push& p : pushes_) p.n = -p.n;
  apply_pushes(w, pushes_, magnitude_);
  return finish(s, detect_us, t1);
}

double Collision::work(const World& w, const Points& dx) const {
  double sum = 0.0;
  if (volume()) {
    // restrict_volume moved node i by dx_i: the equivalent force m dx_i / h^2
    if (!(projected_h_ > 0.0)) return 0.0;
    for (const auto& [i, d] : volume_step_.moves) sum += w.m[i] / (projected_h_ * projected_h_) * d.dot(dx[i]);
    return sum;
  }
  if (projects()) {
    // project_pushes moved the guest by inv_g lambda n and host k by -w_k inv_k lambda n: the
    // equivalent forces m dx / h^2 (kinematic nodes do not move).
    if (!(projected_h_ > 0.0)) return 0.0;
    const double h2 = projected_h_ * projected_h_;
    auto inv = [&w](int i) { return w.is_free(i) ? w.inv_m[i] : 0.0; };
    for (const Push& p : pushes_) {
      if (p.count == 0 || !(p.depth > 0.0) || p.normal.squaredNorm() == 0.0) continue;
      double denom = inv(p.guest);
      for (int k = 0; k < p.count; ++k) denom += p.weight[k] * p.weight[k] * inv(p.hosts[k]);
      if (!(denom > 0.0)) continue;
      const double lambda = p.depth / denom;
      double s = w.m[p.guest] * inv(p.guest) * p.normal.dot(dx[p.guest]);
      for (int k = 0; k < p.count; ++k) s -= p.weight[k] * w.m[p.hosts[k]] * inv(p.hosts[k]) * p.normal.dot(dx[p.hosts[k]]);
      sum += lambda / h2 * s;
    }
    return sum;
  }
  if (response_) {
    for (std::size_t i = 0; i < response_f_.size() && i < dx.size(); ++i) sum += response_f_[i].dot(dx[i]);
    return sum;
  }
  for (std::size_t i = 0; i < pushes_.size() && i < magnitude_.size(); ++i) {
    const Push& p = pushes_[i];
    if (p.count == 0) continue;
    double s = p.n.dot(dx[p.guest]);
    for (int k = 0; k < p.count; ++k) s -= p.weight[k] * p.n.dot(dx[p.hosts[k]]);
    sum += magnitude_[i] * s;
  }
  return sum;
}

}  // namespace harness
