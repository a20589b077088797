#include "core/effects/contact.hpp"

#include "core/collision/responses/force_rule.hpp"
#include "core/scene/scene.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace harness {

namespace {
// The rule's stiffness at a depth of the pair's length scale (magnitude 0): what the guard
// assumes before the first step. A pair is stiff when its rule reports a stiffness there (a
// response of the program's reports none).
double nominal_stiffness(const Pair& p) {
  const auto k = p.collision->rule().stiffness;
  const double v = k ? k(p.spec.force_parameters, p.collision->length(), 0.0) : 0.0;
  return std::isfinite(v) && v > 0.0 ? v : 0.0;
}
bool stiff(const Pair& p) {
  return p.collision && !p.collision->has_response() && nominal_stiffness(p) > 0.0;
}
// The contact stiffness (N/m) of push i along its direction: the rule's, at the push's depth.
double push_stiffness(const Pair& p, std::size_t i) {
  const Push& q = p.collision->pushes()[i];
  const double k = p.collision->rule().stiffness(p.spec.force_parameters, q.depth, p.collision->magnitudes()[i]);
  return std::isfinite(k) && k > 0.0 ? k : 0.0;
}
}  // namespace

void ContactEffect::begin_step(World&, const StepContext&) {
  for (Pair& p : pairs_) p.last = PairStep{};
}

void ContactEffect::add_forces(World& w, const StepContext& s) {
  for (Pair& p : pairs_) {
    const PairStep st = p.collision->step(w, s.h);
    p.last.contacts += st.contacts;
    if (st.beyond_band >= 0) p.last.beyond_band = std::max(0, p.last.beyond_band) + st.beyond_band;
    p.last.detect_us += st.detect_us;
    p.last.eliminate_us += st.eliminate_us;
    p.last.force = std::max(p.last.force, st.force);
  }
}

int ContactEffect::ahead_tasks() const {
  int n = 0;
  for (const Pair& p : pairs_)
    if (p.collision) n += p.collision->ahead_parts();
  return n;
}

void ContactEffect::detect_ahead(const World& w, int task) {
  for (Pair& p : pairs_) {
    const int parts = p.collision ? p.collision->ahead_parts() : 0;
    if (task < parts) return p.collision->detect_ahead(w, task);
    task -= parts;
  }
}

void ContactEffect::ahead_done() {
  for (Pair& p : pairs_)
    if (p.collision && p.collision->ahead_parts() > 0) p.collision->ahead_done();
}

void ContactEffect::after_integration(World& w, const StepContext& s) {
  for (Pair& p : pairs_) {
    if (!p.collision->projects()) continue;
    const PairStep st = p.collision->project(w, s.h);
    p.last.contacts += st.contacts;
    if (st.beyond_band >= 0) p.last.beyond_band = std::max(0, p.last.beyond_band) + st.beyond_band;
    p.last.detect_us += st.detect_us;
    p.last.eliminate_us += st.eliminate_us;
    p.last.force = std::max(p.last.force, st.force);
  }
}

bool ContactEffect::corrects_positions() const {
  for (const Pair& p : pairs_)
    if (p.collision->projects()) return true;
  return false;
}

void ContactEffect::end_step(World&, const StepContext& s) {
  if (s.substeps > 1)
    for (Pair& p : pairs_) {
      p.last.contacts = (p.last.contacts + s.substeps - 1) / s.substeps;
      // Rounded up like `contacts`: one node beyond the band in one substep still counts.
      if (p.last.beyond_band > 0) p.last.beyond_band = (p.last.beyond_band + s.substeps - 1) / s.substeps;
    }
}

double ContactEffect::work(const World& w, const Points& dx) const {
  double sum = 0.0;
  for (const Pair& p : pairs_)
    if (p.collision && p.collision->stepped()) sum += p.collision->work(w, dx);
  return sum;
}

bool ContactEffect::has_stiffness() const {
  for (const Pair& p : pairs_)
    if (stiff(p)) return true;
  return false;
}

bool ContactEffect::add_stiffness_rows(const World& w, std::vector<Vec3>& rows) const {
  bool any = false;
  for (const Pair& p : pairs_) {
    if (!stiff(p)) continue;
    any = true;
    if (!p.collision->stepped()) {  // before the first step: the rule's at a depth of the pair's length scale
      const double k = nominal_stiffness(p);
      const Body& g = w.bodies[p.spec.guest];
      for (int i = g.begin; i < g.end; ++i) rows[i] += Vec3::Constant(2.0 * k);
      continue;
    }
    const auto& pushes = p.collision->pushes();
    const auto& mag = p.collision->magnitudes();
    for (std::size_t i = 0; i < pushes.size(); ++i) {
      const Push& q = pushes[i];
      if (q.count == 0 || !(mag[i] > 0.0)) continue;
      const double k = push_stiffness(p, i);
      if (k == 0.0) continue;
      const Vec3 a = q.n.cwiseAbs();
      const Vec3 r = (2.0 * k * a.sum()) * a;
      rows[q.guest] += r;
      for (int h = 0; h < q.count; ++h) rows[q.hosts[h]] += q.weight[h] * r;
    }
  }
  return any;
}

void ContactEffect::add_jacobian(const World&, LinearSystem& sys) const {
  for (const Pair& p : pairs_) {
    if (!stiff(p)) continue;
    if (!p.collision || !p.collision->stepped()) continue;
    const auto& pushes = p.collision->pushes();
    const auto& mag = p.collision->magnitudes();
    for (std::size_t i = 0; i < pushes.size(); ++i) {
      const Push& q = pushes[i];
      if (q.count == 0 || !(mag[i] > 0.0)) continue;
      ContactBlock b;
      b.node[0] = q.guest, b.c[0] = 1.0;
      for (int h = 0; h < q.count && h < 3; ++h) b.node[h + 1] = q.hosts[h], b.c[h + 1] = -q.weight[h];
      b.count = 1 + std::min(q.count, 3);
      b.n = q.n;
      b.k = push_stiffness(p, i);
      sys.contacts.push_back(b);
    }
  }
}

std::unique_ptr<Effect> make_contact_effect(EffectBuild& b) {
  for (std::size_t i = 0; i < b.pairs.size(); ++i) {
    Pair& p = b.pairs[i];
    if (const DetectorDef* d = find_detector(p.spec.detector); d && d->exact && !b.exact_detectors)
      throw InputError(b.scene.file + ": " + b.scene.contacts[i].path + ".detector",
                       std::string("detector \"") + d->name +
                           "\" needs the reference library (FCL, CGAL), which this program was built without");
    try {
      p.collision = std::make_unique<Collision>(b.world, p.spec, b.exact_detectors);
    } catch (const std::invalid_argument& e) {
      throw InputError(b.scene.file + ": " + b.scene.contacts[i].path, e.what());
    }
  }
  return std::make_unique<ContactEffect>(b.pairs);
}

}  // namespace harness
