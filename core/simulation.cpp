#include "core/simulation.hpp"

#include "core/clock.hpp"
#include "core/mesh.hpp"
#include "core/integrator.hpp"
#include "core/shapes.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>

namespace harness {

namespace {


ShapeModel generate(const Scene& sc, const BodySpec& b) {
  const ShapeSpec& s = b.shape;
  const Fill fill = s.volume_fill ? Fill::volume : Fill::shell;
  try {
    if (s.type == "box") return make_box(s.min, s.max, s.cells);
    if (s.type == "sphere") return make_sphere(s.center, s.radius, s.subdivisions, fill);
    if (s.type == "ellipsoid") return make_ellipsoid(s.center, s.radii, s.subdivisions, fill);
    if (s.type == "cylinder")
      return make_cylinder(s.center, s.axis, s.radius, s.length, s.segments, s.rings, fill);
    SurfaceMesh mesh;
    try {
      mesh = read_surface(s.path);
    } catch (const InputError& e) {
      throw InputError(sc.file + ": " + b.path + ".shape.path", e.what());
    }
    return make_from_surface(mesh, s.scale, s.translate, fill);
  } catch (const std::invalid_argument& e) {
    throw InputError(sc.file + ": " + b.path + ".shape", e.what());
  }
}

}  // namespace

std::vector<int> select_nodes(const World& w, int body, const Selection& sel) {
  const Body& b = w.bodies[body];
  std::vector<int> out;
  const double diag = (b.rest_max - b.rest_min).norm();
  const double tol = 1e-6 * diag;
  for (int i = b.begin; i < b.end; ++i) {
    const Vec3& p = w.x0[i];
    bool in = false;
    switch (sel.kind) {
      case Selection::all: in = true; break;
      case Selection::side:
        in = sel.sign < 0 ? p[sel.axis] <= b.rest_min[sel.axis] + tol
                          : p[sel.axis] >= b.rest_max[sel.axis] - tol;
        break;
      case Selection::box:
        in = (p.array() >= sel.min.array() - 1e-12 * diag).all() &&
             (p.array() <= sel.max.array() + 1e-12 * diag).all();
        break;
    }
    if (in) out.push_back(i);
  }
  return out;
}

namespace {

// Stiffness of spring s of a generated body (N/m): material.stiffness, or from
// material.youngs_modulus through the generator's factor (elastic_map.hpp).
double spring_stiffness(const Material& m, const ShapeModel& model, std::size_t s) {
  if (!(m.youngs_modulus > 0.0)) return m.stiffness;
  const double E = m.youngs_modulus, t = m.thickness, kappa = model.spring_kappa[s];
  switch (model.spring_role[s]) {
    case SpringRole::volume: return E * kappa;
    case SpringRole::membrane: return E * t * kappa;
    case SpringRole::bending: return E * t * t * t * kappa;
  }
  return E * kappa;
}

// Appends a generated body to the world's arrays (nodes, springs, masses) and its topology.
void append_body(World& w, const BodySpec& bs, ShapeModel&& model) {
  Body b;
  b.name = bs.name;
  b.begin = w.num_nodes();
  b.end = b.begin + static_cast<int>(model.nodes.size());
  b.n_surface = model.n_surface;
  b.faces = std::move(model.faces);
  b.material = bs.material;
  b.volume = model.volume;
  // Vertex -> face CSR for vertex normals.
  b.vf_start.assign(b.n_surface + 1, 0);
  for (const Tri& t : b.faces)
    for (int v : t) ++b.vf_start[v + 1];
  for (int s = 0; s < b.n_surface; ++s) b.vf_start[s + 1] += b.vf_start[s];
  b.vf_faces.assign(b.vf_start.back(), 0);
  std::vector<int> fill(b.vf_start.begin(), b.vf_start.end() - 1);
  for (std::size_t fi = 0; fi < b.faces.size(); ++fi)
    for (int v : b.faces[fi]) b.vf_faces[fill[v]++] = static_cast<int>(fi);
  b.rest_min = Vec3::Constant(std::numeric_limits<double>::infinity());
  b.rest_max = -b.rest_min;
  for (const Vec3& p : model.nodes) {
    b.rest_min = b.rest_min.cwiseMin(p);
    b.rest_max = b.rest_max.cwiseMax(p);
  }
  const int body_index = static_cast<int>(w.bodies.size());
  b.spring_begin = static_cast<int>(w.springs.size());
  for (std::size_t s = 0; s < model.springs.size(); ++s) {
    const Edge& e = model.springs[s];
    w.springs.ends.push_back({b.begin + e[0], b.begin + e[1]});
    w.springs.rest.push_back((model.nodes[e[1]] - model.nodes[e[0]]).norm());
    w.springs.k.push_back(spring_stiffness(bs.material, model, s));
    w.springs.body.push_back(body_index);
  }
  b.spring_end = static_cast<int>(w.springs.size());
  for (std::size_t i = 0; i < model.nodes.size(); ++i) {
    w.x.push_back(model.nodes[i]);
    w.v.push_back(bs.velocity);
    w.m.push_back(bs.material.density * model.node_volume[i]);
  }
  w.body_law.push_back({bs.material.law, bs.material.nonlinearity});
  w.bodies.push_back(std::move(b));
}

}  // namespace

Simulation::Simulation(const Scene& scene, const SimulationOptions& options)
    : scene_(scene), audit_(options.audit) {
  build_world();
  build_kinematics();
  build_pairs();
  build_effects(options);
  guard_ = std::make_unique<StabilityGuard>(scene_, world_, effects_);
  if (options.engine) {
    engine_ = options.engine(scene_, world_);  // may throw InputError: nothing written yet
    if (scene_.has(kContact))
      for (Pair& p : pairs_) p.engine_contact = engine_->contact_model();
    engine_v_prev_.assign(world_.x.size(), Vec3::Zero());
  }
  stats_.stability = guard_->stats();
  if (audit_) {
    category_force_.assign(kCategories, Points());
    for (const auto& e : effects_)  // sized once: only the categories that are built
      if (e->category() != EffectCategory::none)
        category_force_[static_cast<int>(e->category())].assign(world_.x.size(), Vec3::Zero());
    category_prev_ = category_force_;
    driver_force_.assign(world_.x.size(), Vec3::Zero());
    driver_prev_ = disp_prev_ = driver_force_;
    reset_energy();
  } else {
    residual_ = std::numeric_limits<double>::quiet_NaN();
  }
}

void Simulation::build_world() {
  World& w = world_;
  for (const BodySpec& bs : scene_.bodies) append_body(w, bs, generate(scene_, bs));
  const int n = w.num_nodes();
  for (int i = 0; i < n; ++i) {
    if (!(w.m[i] > 0.0) || !std::isfinite(w.m[i]))
      throw InputError(scene_.file + ": bodies", "a node has no positive mass (check density and shape)");
    w.inv_m.push_back(1.0 / w.m[i]);
  }
  w.x0 = w.x;
  w.f.assign(n, Vec3::Zero());
  w.kinematic.assign(n, Kinematic::free);
  w.kin_v.assign(n, Vec3::Zero());
}

// Selections are resolved and checked whether or not their effect is listed: a bad scene is
// bad input either way.
void Simulation::build_kinematics() {
  for (std::size_t bi = 0; bi < scene_.bodies.size(); ++bi) {
    const BodySpec& bs = scene_.bodies[bi];
    for (const Selection& sel : bs.pins) {
      const auto nodes = select_nodes(world_, static_cast<int>(bi), sel);
      if (nodes.empty()) throw InputError(scene_.file + ": " + sel.path, "selection selects no node");
      pinned_nodes_.insert(pinned_nodes_.end(), nodes.begin(), nodes.end());
    }
    for (std::size_t d = 0; d < bs.drivers.size(); ++d) {
      const DriverSpec& ds = bs.drivers[d];
      auto nodes = select_nodes(world_, static_cast<int>(bi), ds.select);
      if (nodes.empty())
        throw InputError(scene_.file + ": " + bs.path + ".drivers." + std::to_string(d) + ".select",
                         "selection selects no node");
      drivers_.push_back({std::move(nodes), ds.velocity, ds.from_step, ds.to_step});
    }
    for (std::size_t l = 0; l < bs.loads.size(); ++l) {
      const LoadSpec& ls = bs.loads[l];
      auto nodes = select_nodes(world_, static_cast<int>(bi), ls.select);
      if (nodes.empty())
        throw InputError(scene_.file + ": " + bs.path + ".loads." + std::to_string(l) + ".select",
                         "selection selects no node");
      loads_.push_back({std::move(nodes), ls.force, ls.ramp_steps});
    }
  }
}

void Simulation::build_pairs() {
  for (const ContactPairSpec& cp : scene_.contacts) {
    Pair p;
    p.spec = cp.spec;
    p.spec.host = world_.find_body(cp.host);
    p.spec.guest = world_.find_body(cp.guest);
    p.label = cp.host + "/" + cp.guest;
    pairs_.push_back(std::move(p));
  }
}

void Simulation::build_effects(const SimulationOptions& options) {
  // With a peer engine the engine handles contact: the pairs stay (measured, recorded) without
  // the harness's detection and response.
  Scene built = scene_;
  if (options.engine) built.effects &= ~static_cast<unsigned>(kContact);
  EffectBuild b{built, world_, pairs_, pinned_nodes_, drivers_, loads_, options.exact_detectors};
  effects_ = make_effects(b);
}

std::vector<std::string> Simulation::effects_simulated() const {
  std::vector<std::string> out;
  for (const EffectEntry& e : effect_table())
    if (scene_.effects & e.flag) out.push_back(e.name);
  return out;
}

void Simulation::integrate(const StepContext& s) {
  if (scene_.integrator == Integrator::symplectic_euler) return symplectic_euler_step(world_, s.h);
  system_.reset(world_);
  for (const auto& e : effects_) e->add_jacobian(world_, system_);
  stats_.implicit_last = implicit_.step(world_, s.h, system_);
  stats_.implicit_max_iterations = std::max(stats_.implicit_max_iterations, stats_.implicit_last.iterations);
  if (!stats_.implicit_last.converged) ++stats_.implicit_unconverged;
}

void Simulation::step() {
  if (engine_) return engine_step();
  const auto t0 = Clock::now();
  ++step_index_;
  World& w = world_;
  guard_->before_step(w, effects_, step_index_);
  const int substeps = guard_->substeps();
  const StepContext ctx{step_index_, scene_.dt, scene_.dt / substeps, substeps};
  const double ke_before = audit_ ? kinetic_energy() : 0.0;
  for (const auto& e : effects_) e->begin_step(w, ctx);
  // Drivers starting their nodes (before the first step E*_0 holds it already).
  if (audit_ && ledger_.started) ledger_.work_external += kinetic_energy() - ke_before;
  double total = 0.0;
  for (int s = 0; s < substeps; ++s) {
    const auto ts = Clock::now();
    std::fill(w.f.begin(), w.f.end(), Vec3::Zero());
    add_forces(ctx);
    if (audit_) v_before_ = w.v;
    integrate(ctx);
    after_integration(ctx);
    if (audit_) book_work(ctx.h);
    total += us_since(ts);
  }
  for (const auto& e : effects_) e->end_step(w, ctx);
  if (audit_) {
    ledger_.kinetic = kinetic_energy();
    ledger_.elastic = elastic_start_;
    ledger_.work_contact_peak = std::max(ledger_.work_contact_peak, ledger_.work_contact);
    update_residual();
  }
  last_.detect_us = last_.eliminate_us = 0.0;
  for (const Pair& p : pairs_) last_.detect_us += p.last.detect_us, last_.eliminate_us += p.last.eliminate_us;
  last_.physics_us = total - last_.detect_us - last_.eliminate_us;
  stats_.stability = guard_->stats();
  last_.step_us = us_since(t0);
}

// A peer engine's step: the kinematic effects set the nodes' state, the engine steps; then the
// kinetic and elastic energies and the force residual, where the net force on a free node is
// the one that changed its momentum in the step, m (v_{n+1} - v_n) / dt (the engine's contact
// and constraint corrections included), over the same scale as the harness's own residual.
void Simulation::engine_step() {
  const auto t0 = Clock::now();
  ++step_index_;
  World& w = world_;
  const StepContext ctx{step_index_, scene_.dt, scene_.dt, 1};
  for (const auto& e : effects_) e->begin_step(w, ctx);
  std::copy(w.v.begin(), w.v.end(), engine_v_prev_.begin());
  const EngineStep es = engine_->step(w, step_index_, scene_.dt);
  for (const auto& e : effects_) e->end_step(w, ctx);
  for (std::size_t p = 0; p < pairs_.size(); ++p) {
    pairs_[p].last = PairStep{};
    if (p < es.contacts.size()) pairs_[p].last.contacts = es.contacts[p];
  }
  if (!pairs_.empty()) pairs_[0].last.detect_us = es.detect_us;  // one collision pass for all pairs
  last_.detect_us = es.detect_us;
  last_.eliminate_us = 0.0;  // solved with the links inside the engine's solver: in physics_us
  if (audit_) {
    ledger_.kinetic = kinetic_energy();
    ledger_.elastic = elastic_energy();
    std::fill(w.f.begin(), w.f.end(), Vec3::Zero());
    add_forces(ctx);
    for (int i = 0; i < w.num_nodes(); ++i)
      w.f[i] = w.is_free(i) ? Vec3(w.m[i] * (w.v[i] - engine_v_prev_[i]) / scene_.dt) : Vec3::Zero();
    update_residual();
  }
  last_.step_us = us_since(t0);
  last_.physics_us = last_.step_us - last_.detect_us;
}

// Forces of every effect in table order; with the audit, each category's share is kept by
// snapshots of w.f around the run of effects of that category.
void Simulation::add_forces(const StepContext& s) {
  World& w = world_;
  if (!audit_) {
    for (const auto& e : effects_) e->add_forces(w, s);
    return;
  }
  for (Points& f : category_force_) std::fill(f.begin(), f.end(), Vec3::Zero());
  EffectCategory open = EffectCategory::none;
  for (const auto& e : effects_) {
    if (e->category() != open) {
      close_category(open);
      open = e->category();
      if (open != EffectCategory::none) mark_ = w.f;
    }
    e->add_forces(w, s);
  }
  close_category(open);
}

// Position-based corrections; with the audit, the equivalent forces they add into w.f are booked
// with their effect's category.
void Simulation::after_integration(const StepContext& s) {
  World& w = world_;
  for (const auto& e : effects_) {
    if (!e->corrects_positions()) continue;
    if (!audit_ || e->category() == EffectCategory::none) {
      e->after_integration(w, s);
      continue;
    }
    mark_ = w.f;
    e->after_integration(w, s);
    close_category(e->category());
  }
}

void Simulation::close_category(EffectCategory c) {
  if (c == EffectCategory::none) return;
  Points& f = category_force_[static_cast<int>(c)];
  for (std::size_t i = 0; i < f.size(); ++i) f[i] += world_.f[i] - mark_[i];
}

// After the substep from x_n: books the trapezoidal work of the interval x_{n-1} -> x_n (the
// forces at both ends, the displacement of the substep before), then E*_n (energy.hpp); keeps
// this substep's forces and displacement for the next.
void Simulation::book_work(double h) {
  const World& w = world_;
  const int n = w.num_nodes();
  double ke_staggered = 0.0;
  for (int i = 0; i < n; ++i) {
    ke_staggered += 0.5 * w.m[i] * v_before_[i].dot(w.v[i]);
    driver_force_[i] = w.kinematic[i] == Kinematic::driven ? Vec3(-w.f[i]) : Vec3::Zero();
  }
  if (have_prev_) book_interval();
  ledger_.staggered = ke_staggered + elastic_start_;
  if (!ledger_.started) ledger_.staggered0 = ledger_.staggered, ledger_.started = true;
  for (int i = 0; i < n; ++i)
    disp_prev_[i] = w.kinematic[i] == Kinematic::pinned ? Vec3::Zero()
                    : w.kinematic[i] == Kinematic::driven ? Vec3(h * w.kin_v[i])
                                                          : Vec3(h * w.v[i]);
  std::swap(category_force_, category_prev_);
  std::swap(driver_force_, driver_prev_);
  have_prev_ = true;
  elastic_start_ = elastic_energy();
}

void Simulation::book_interval() {
  const World& w = world_;
  double work[kCategories] = {};
  double drivers = 0.0;
  for (int i = 0; i < w.num_nodes(); ++i) {
    const Vec3& d = disp_prev_[i];
    for (int c = 0; c < kCategories; ++c)
      if (!category_force_[c].empty()) work[c] += 0.5 * (category_prev_[c][i] + category_force_[c][i]).dot(d);
    drivers += 0.5 * (driver_prev_[i] + driver_force_[i]).dot(d);
  }
  ledger_.work_external += work[static_cast<int>(EffectCategory::external)] + drivers;
  ledger_.dissipated -= work[static_cast<int>(EffectCategory::dissipative)];
  ledger_.work_contact += work[static_cast<int>(EffectCategory::contact)];
}

void Simulation::update_residual() {
  const World& w = world_;
  const Points& ext = category_force_[static_cast<int>(EffectCategory::external)];
  const Points& el = category_force_[static_cast<int>(EffectCategory::elastic)];
  double net = 0.0, applied = 0.0, springs = 0.0;
  for (int i = 0; i < w.num_nodes(); ++i) {
    if (!w.is_free(i)) continue;
    net += w.f[i].squaredNorm();
    if (!ext.empty()) applied += ext[i].squaredNorm();
    if (!el.empty()) springs += el[i].squaredNorm();
  }
  // Without applied forces, free bodies come to rest with their springs relaxed: the scale is
  // then the largest spring-force norm seen in the run.
  spring_force_peak_ = std::max(spring_force_peak_, springs);
  const double scale = applied > 0.0 ? applied : spring_force_peak_;
  residual_ = scale > 0.0 ? std::sqrt(net / scale) : 0.0;
}

void Simulation::restore(const Points& x, const Points& v, int step) {
  std::copy(x.begin(), x.end(), world_.x.begin());
  std::copy(v.begin(), v.end(), world_.v.begin());
  step_index_ = step;
}

double Simulation::kinetic_energy() const {
  double e = 0.0;
  for (int i = 0; i < world_.num_nodes(); ++i) e += 0.5 * world_.m[i] * world_.v[i].squaredNorm();
  return e;
}

double Simulation::potential_energy() const {
  double e = 0.0;
  for (const auto& f : effects_) e += f->energy(world_);
  return e;
}

void Simulation::reset_energy() {
  ledger_ = EnergyLedger{};
  ledger_.kinetic = kinetic_energy();
  ledger_.elastic = elastic_start_ = elastic_energy();
  ledger_.initial = ledger_.kinetic + ledger_.elastic;
  have_prev_ = false;
}

double Simulation::elastic_energy() const {
  double e = 0.0;
  for (const auto& f : effects_)
    if (f->category() == EffectCategory::elastic) e += f->energy(world_);
  return e;
}

double Simulation::critical_dt() const {
  std::vector<Vec3> rows;
  return harness::critical_dt(world_, effects_, rows);
}

std::string state_hash(const World& w) {
  std::uint64_t h = 1469598103934665603ull;
  auto feed = [&h](const Points& p) {
    for (const Vec3& q : p)
      for (int a = 0; a < 3; ++a) {
        unsigned char b[sizeof(double)];
        const double d = q[a];
        std::memcpy(b, &d, sizeof d);
        for (unsigned char c : b) h = (h ^ c) * 1099511628211ull;
      }
  };
  feed(w.x);
  feed(w.v);
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
  return buf;
}

}  // namespace harness
