#include "core/simulation.hpp"

#include "core/clock.hpp"
#include "core/mesh.hpp"
#include "core/integrator.hpp"
#include "core/shapes.hpp"
#include "core/spring_forces.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>

namespace harness {

namespace {

// The booking pass's partial sums (integrate_and_book, book), per chunk of kBookChunk nodes: the
// chunks, not the threads, fix the order of the sums, so the audit and the residual (and so the
// step at which a run settles) are the same for any thread count.
constexpr std::size_t kBookChunk = 4096;
enum BookSum {
  kKeStaggered, kKeNew, kCloseExt, kCloseDiss, kCloseDrv, kPendExt, kPendDiss, kPendDrv, kNet, kApplied, kSprings2,
  kGravityPotential, kBookSums
};

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
  const std::size_t n = world_.x.size();
  for (const auto& e : effects_) {
    external_ = external_ || e->category() == EffectCategory::external;
    corrects_ = corrects_ || e->corrects_positions();
    if (e->category() == EffectCategory::contact) contact_ = e.get();
  }
  drivers_built_ = scene_.has(kDrivers) && !drivers_.empty();
  if (external_) f_ext_.assign(n, Vec3::Zero());  // sized once: no allocation per step
  if (audit_) {
    if (scene_.has(kSprings)) f_spring_.assign(n, Vec3::Zero()), node_energy_.assign(n, 0.0);
    if (scene_.has(kDamping)) {
      f_dashpot_.assign(n, Vec3::Zero());
      mass_damping_.assign(n, 0.0);
      for (const Body& b : world_.bodies)
        for (int i = b.begin; i < b.end; ++i) mass_damping_[i] = b.material.mass_damping;
    }
    disp_prev_.assign(n, Vec3::Zero());
    v_before_.assign(n, Vec3::Zero());
    chunk_sums_.assign(kBookSums * ((n + kBookChunk - 1) / kBookChunk + 1), 0.0);
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
  pairs_.reserve(scene_.contacts.size());
  for (const ContactPairSpec& cp : scene_.contacts) pairs_.emplace_back(cp.spec, cp.host + "/" + cp.guest);
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
  // A due check of the stability guard takes the springs' rows from the first substep's force
  // pass (add_forces); without springs it is made here.
  const bool due = guard_->due(step_index_);
  const bool rows_in_pass = due && scene_.has(kSprings) && !w.springs.ends.empty();
  if (due && !rows_in_pass) guard_->before_step(w, effects_, step_index_);
  const int substeps = guard_->substeps();
  StepContext ctx{step_index_, scene_.dt, scene_.dt / substeps, substeps};
  if (rows_in_pass) {
    std::vector<Vec3>& rows = guard_->rows();
    rows.assign(w.x.size(), Vec3::Zero());  // sized at the guard's first check: no allocation
    ctx.guard_rows = &rows;
  }
  if (audit_) {
    ctx.f_spring = f_spring_.empty() ? nullptr : &f_spring_;
    ctx.f_dashpot = f_dashpot_.empty() ? nullptr : &f_dashpot_;
    ctx.spring_energy = node_energy_.empty() ? nullptr : &node_energy_;
  }
  for (const auto& e : effects_) e->begin_step(w, ctx);
  // Drivers starting or stopping their nodes set their velocities: work put in (before the first
  // step E*_0 holds it already).
  if (audit_ && drivers_built_ && ledger_.started) ledger_.work_external += kinetic_energy() - ledger_.kinetic;
  const bool fused = scene_.integrator == Integrator::symplectic_euler && !corrects_;
  double total = 0.0;
  for (int s = 0; s < ctx.substeps; ++s) {
    const auto ts = Clock::now();
    std::fill(w.f.begin(), w.f.end(), Vec3::Zero());
    add_forces(ctx);
    if (fused) {
      integrate_and_book(ctx);
    } else {
      if (audit_) std::copy(w.v.begin(), w.v.end(), v_before_.begin());
      integrate(ctx);
      after_integration(ctx);
      if (audit_) book(ctx);
    }
    total += us_since(ts);
  }
  for (const auto& e : effects_) e->end_step(w, ctx);
  if (audit_) ledger_.work_contact_peak = std::max(ledger_.work_contact_peak, ledger_.work_contact);
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
  StepContext ctx{step_index_, scene_.dt, scene_.dt, 1};
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
    ctx.f_spring = f_spring_.empty() ? nullptr : &f_spring_;
    ledger_.kinetic = kinetic_energy();
    ledger_.elastic = elastic_energy();
    ledger_.potential = potential_energy();
    std::fill(w.f.begin(), w.f.end(), Vec3::Zero());
    add_forces(ctx);  // the external and springs' forces at the new state: the residual's scales
    double net = 0.0, applied = 0.0, springs = 0.0;
    for (int i = 0; i < w.num_nodes(); ++i) {
      if (!w.is_free(i)) continue;
      net += (w.m[i] * (w.v[i] - engine_v_prev_[i]) / scene_.dt).squaredNorm();
      if (external_) applied += f_ext_[i].squaredNorm();
      if (ctx.f_spring) springs += f_spring_[i].squaredNorm();
    }
    spring_force_peak_ = std::max(spring_force_peak_, springs);
    const double scale = applied > 0.0 ? applied : spring_force_peak_;
    residual_ = scale > 0.0 ? std::sqrt(net / scale) : 0.0;
  }
  last_.step_us = us_since(t0);
  last_.physics_us = last_.step_us - last_.detect_us;
}

// Forces of every effect in table order into w.f, the external effects' (gravity, pressure,
// loads) into f_ext_ (w.f swapped with it while they run: no copy), which joins w.f before the
// contact effect (whose automatic force reads every other force) runs, or at the end. The same
// order with the audit on or off: the state's bits never depend on it.
void Simulation::add_forces(StepContext& s) {
  World& w = world_;
  // The guard's check, once the springs' pass left their rows: before any force that depends on
  // the substep (contact), which may change now.
  auto check_guard = [&] {
    if (!s.guard_rows) return;
    s.guard_rows = nullptr;
    guard_->check_with_rows(w, effects_);
    s.substeps = guard_->substeps();
    s.h = s.dt / s.substeps;
  };
  if (external_) std::fill(f_ext_.begin(), f_ext_.end(), Vec3::Zero());
  bool joined = !external_;
  auto join = [&] {
    const int n = w.num_nodes();
    const int T = threads_for(static_cast<std::size_t>(n));
#pragma omp parallel for num_threads(T) if(T > 1) schedule(static)
    for (int i = 0; i < n; ++i) w.f[i] += f_ext_[i];
    joined = true;
  };
  for (const auto& e : effects_) {
    if (e->category() != EffectCategory::elastic) check_guard();
    if (e->category() == EffectCategory::external) {
      std::swap(w.f, f_ext_);
      e->add_forces(w, s);
      std::swap(w.f, f_ext_);
      continue;
    }
    if (e->category() == EffectCategory::contact && !joined) join();
    e->add_forces(w, s);
  }
  if (!joined) join();
  check_guard();
}

// Position-based corrections (their equivalent forces go into w.f; the contact effect's work()
// books them).
void Simulation::after_integration(const StepContext& s) {
  for (const auto& e : effects_)
    if (e->corrects_positions()) e->after_integration(world_, s);
}

namespace {

// The audit's share of one node's booking (energy.hpp): f the total force of the substep at x_n,
// v_old = v_{n-1/2}, v_new = v_{n+1/2}, dx_new its displacement x_{n+1} - x_n, dx_prev the one
// before. Each category's force at x_n closes the interval before (half of it dotted with
// dx_prev) and opens the one after (half dotted with dx_new).
struct BookInput {
  const World& w;
  const Points* f_ext;       // null without external effects
  const Points* f_dashpot;   // null without the damping effect
  const std::vector<double>* mass_damping;
  const Points* f_spring;    // null without springs
  Vec3 gravity;
  bool gravity_on;
};

inline void book_node(const BookInput& in, int i, const Vec3& f, const Vec3& v_old, const Vec3& v_new,
                      const Vec3& dx_new, const Vec3& dx_prev, double* acc) {
  const World& w = in.w;
  const double m = w.m[i];
  acc[kKeStaggered] += 0.5 * m * v_old.dot(v_new);
  acc[kKeNew] += 0.5 * m * v_new.squaredNorm();
  if (in.f_ext) {
    const Vec3& fe = (*in.f_ext)[i];
    acc[kCloseExt] += 0.5 * fe.dot(dx_prev);
    acc[kPendExt] += 0.5 * fe.dot(dx_new);
  }
  if (in.f_dashpot) {
    const Vec3 fd = (*in.f_dashpot)[i] - ((*in.mass_damping)[i] * m) * v_old;
    acc[kCloseDiss] += 0.5 * fd.dot(dx_prev);
    acc[kPendDiss] += 0.5 * fd.dot(dx_new);
  }
  if (w.kinematic[i] == Kinematic::driven) {  // the driver holds its node against every force on it
    acc[kCloseDrv] -= 0.5 * f.dot(dx_prev);
    acc[kPendDrv] -= 0.5 * f.dot(dx_new);
  }
  if (w.is_free(i)) {
    acc[kNet] += f.squaredNorm();
    if (in.f_ext) acc[kApplied] += (*in.f_ext)[i].squaredNorm();
    if (in.f_spring) acc[kSprings2] += (*in.f_spring)[i].squaredNorm();
  }
}

}  // namespace

// Symplectic Euler (integrator.hpp: the same operations, bit for bit) with the audit's booking in
// the same pass over the nodes, in chunks whose partial sums are added in chunk order.
void Simulation::integrate_and_book(const StepContext& s) {
  World& w = world_;
  const double h = s.h;
  if (!audit_) return symplectic_euler_step(w, h);
  const double close_contact = contact_ ? 0.5 * contact_->work(w, disp_prev_) : 0.0;
  const BookInput in{w, external_ ? &f_ext_ : nullptr, f_dashpot_.empty() ? nullptr : &f_dashpot_, &mass_damping_,
                     f_spring_.empty() ? nullptr : &f_spring_, scene_.gravity, scene_.has(kGravity)};
  const std::size_t n = w.x.size(), chunks = (n + kBookChunk - 1) / kBookChunk;
  const int T = threads_for(n);
#pragma omp parallel for num_threads(T) if(T > 1) schedule(dynamic, 1)
  for (std::size_t c = 0; c < chunks; ++c) {
    double acc[kBookSums] = {};
    for (std::size_t k = c * kBookChunk; k < std::min(n, (c + 1) * kBookChunk); ++k) {
      const int i = static_cast<int>(k);
      const Vec3 f = w.f[i], v_old = w.v[i];
      if (in.gravity_on) acc[kGravityPotential] -= w.m[i] * in.gravity.dot(w.x[i]);
      Vec3 dx = Vec3::Zero();
      switch (w.kinematic[i]) {
        case Kinematic::free:
          w.v[i] += (h * w.inv_m[i]) * f;
          w.x[i] += h * w.v[i];
          dx = h * w.v[i];
          break;
        case Kinematic::pinned: break;
        case Kinematic::driven:
          w.x[i] += h * w.kin_v[i];
          dx = h * w.kin_v[i];
          break;
      }
      book_node(in, i, f, v_old, w.v[i], dx, disp_prev_[i], acc);
      disp_prev_[i] = dx;
    }
    std::copy(acc, acc + kBookSums, chunk_sums_.begin() + static_cast<std::ptrdiff_t>(c * kBookSums));
  }
  double sums[kBookSums] = {};
  for (std::size_t c = 0; c < chunks; ++c)
    for (int k = 0; k < kBookSums; ++k) sums[k] += chunk_sums_[c * kBookSums + k];
  const double open_contact = contact_ ? 0.5 * contact_->work(w, disp_prev_) : 0.0;
  ledger_.work_contact += pending_[3] + close_contact;
  pending_[3] = open_contact;
  close_substep(s, sums);
}

// The general path's booking, after the integrator and the position corrections: the same sums
// from the velocities before the update (v_before_) and after it.
void Simulation::book(const StepContext& s) {
  World& w = world_;
  const double h = s.h;
  const double close_contact = contact_ ? 0.5 * contact_->work(w, disp_prev_) : 0.0;
  const BookInput in{w, external_ ? &f_ext_ : nullptr, f_dashpot_.empty() ? nullptr : &f_dashpot_, &mass_damping_,
                     f_spring_.empty() ? nullptr : &f_spring_, scene_.gravity, scene_.has(kGravity)};
  const std::size_t n = w.x.size(), chunks = (n + kBookChunk - 1) / kBookChunk;
  for (std::size_t c = 0; c < chunks; ++c) {
    double acc[kBookSums] = {};
    for (std::size_t k = c * kBookChunk; k < std::min(n, (c + 1) * kBookChunk); ++k) {
      const int i = static_cast<int>(k);
      const Vec3 dx = w.kinematic[i] == Kinematic::pinned  ? Vec3(Vec3::Zero())
                      : w.kinematic[i] == Kinematic::driven ? Vec3(h * w.kin_v[i])
                                                            : Vec3(h * w.v[i]);
      if (in.gravity_on) acc[kGravityPotential] -= w.m[i] * in.gravity.dot(w.x[i] - dx);
      book_node(in, i, w.f[i], v_before_[i], w.v[i], dx, disp_prev_[i], acc);
      disp_prev_[i] = dx;
    }
    std::copy(acc, acc + kBookSums, chunk_sums_.begin() + static_cast<std::ptrdiff_t>(c * kBookSums));
  }
  double sums[kBookSums] = {};
  for (std::size_t c = 0; c < chunks; ++c)
    for (int k = 0; k < kBookSums; ++k) sums[k] += chunk_sums_[c * kBookSums + k];
  const double open_contact = contact_ ? 0.5 * contact_->work(w, disp_prev_) : 0.0;
  ledger_.work_contact += pending_[3] + close_contact;
  pending_[3] = open_contact;
  close_substep(s, sums);
}

// Closes the interval before this substep's force point in the ledger, opens the one after it,
// and takes the staggered energy E*_n, the energies and the force residual (energy.hpp).
void Simulation::close_substep(const StepContext& s, const double* sums) {
  (void)s;
  ledger_.work_external += (pending_[0] + sums[kCloseExt]) + (pending_[2] + sums[kCloseDrv]);
  ledger_.dissipated -= pending_[1] + sums[kCloseDiss];
  pending_[0] = sums[kPendExt], pending_[1] = sums[kPendDiss], pending_[2] = sums[kPendDrv];
  const double U = node_energy_.empty() ? 0.0 : sum_node_energy(node_energy_);  // at x_n
  ledger_.staggered = sums[kKeStaggered] + U;
  if (!ledger_.started) ledger_.staggered0 = ledger_.staggered, ledger_.started = true;
  ledger_.kinetic = sums[kKeNew];
  ledger_.elastic = U;
  ledger_.potential = U + sums[kGravityPotential];
  // Without applied forces, free bodies come to rest with their springs relaxed: the scale is
  // then the largest spring-force norm seen in the run.
  spring_force_peak_ = std::max(spring_force_peak_, sums[kSprings2]);
  const double scale = sums[kApplied] > 0.0 ? sums[kApplied] : spring_force_peak_;
  residual_ = scale > 0.0 ? std::sqrt(sums[kNet] / scale) : 0.0;
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
  ledger_.elastic = elastic_energy();
  ledger_.potential = potential_energy();
  ledger_.initial = ledger_.kinetic + ledger_.elastic;
  std::fill(pending_, pending_ + 4, 0.0);
  std::fill(disp_prev_.begin(), disp_prev_.end(), Vec3::Zero());
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
