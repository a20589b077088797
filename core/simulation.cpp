#include "core/simulation.hpp"

#include "core/clock.hpp"
#include "core/collision/responses/plugin.hpp"
#include "core/integrator.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

namespace harness {

Simulation::Simulation(const Scene& scene, const SimulationOptions& options) : scene_(scene) {
  implicit_.tolerance = scene_.cg_tolerance;
  world_ = build_world(scene_, options.layout);
  kinematics_ = resolve_kinematics(scene_, world_);
  if (options.jitter > 0.0) jitter_positions(world_, options.jitter, options.jitter_seed);
  build_pairs();
  build_effects(options);
  attach_responses(options);
  guard_ = std::make_unique<StabilityGuard>(scene_, world_, effects_);
  if (options.engine) {
    engine_ = options.engine(scene_, world_);  // may throw InputError: nothing written yet
    if (scene_.has(kContact))
      for (Pair& p : pairs_) p.engine_contact = engine_->contact_model();
    engine_v_prev_.assign(world_.x.size(), Vec3::Zero());
  }
  stats_.stability = guard_->stats();
  Effect* contact = nullptr;
  for (const auto& e : effects_) {
    external_ = external_ || e->category() == EffectCategory::external;
    corrects_ = corrects_ || e->corrects_positions();
    if (e->category() == EffectCategory::contact) contact = e.get();
  }
  if (contact && contact->ahead_tasks() > 0 && options.overlap != SimulationOptions::Overlap::never) ahead_ = contact;
  overlap_ = options.overlap;
  user_forces_ = options.user_forces;
  if (external_ || user_forces_) f_ext_.assign(world_.x.size(), Vec3::Zero());  // sized once: no allocation per step
  if (options.audit) {
    AuditSetup a;
    a.springs = scene_.has(kSprings) || scene_.has(kBulk);  // the elastic forces and energy per node
    a.damping = scene_.has(kDamping);
    a.gravity = scene_.has(kGravity);
    a.gravity_acceleration = scene_.gravity;
    a.drivers = scene_.has(kDrivers) && !kinematics_.drivers.empty();
    a.f_ext = external_ || user_forces_ ? &f_ext_ : nullptr;
    a.contact = contact;
    audit_ = std::make_unique<EnergyAudit>(world_, a);
    reset_energy();
  }
}

void jitter_positions(World& w, double share, std::uint64_t seed) {
  // splitmix64 of (seed, body, scene index, coordinate): uniform in [-1, 1).
  auto unit = [seed](std::uint64_t a) {
    std::uint64_t z = seed * 0x9E3779B97F4A7C15ull + a + 0x632BE59BD9B4E019ull;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    z ^= z >> 31;
    return static_cast<double>(z >> 11) * 0x1.0p-52 - 1.0;
  };
  for (int b = 0; b < static_cast<int>(w.bodies.size()); ++b) {
    const Body& body = w.bodies[b];
    const double amp = share * rest_spring_length(w, b);
    for (int k = 0; k < body.size(); ++k) {
      const int i = body.begin + k;
      if (!w.is_free(i)) continue;
      const auto key = (static_cast<std::uint64_t>(b) << 40) ^ (static_cast<std::uint64_t>(body.scene_index(k)) << 2);
      for (int c = 0; c < 3; ++c) w.x[i][c] += amp * unit(key + static_cast<std::uint64_t>(c));
    }
  }
}

void Simulation::build_pairs() {
  pairs_.reserve(scene_.contacts.size());
  for (const ContactPairSpec& cp : scene_.contacts) pairs_.emplace_back(cp.spec, cp.label);
}

void Simulation::attach_responses(const SimulationOptions& options) {
  if (options.responses.size() > pairs_.size())
    throw InputError(scene_.file + ": contacts", "a response for pair " + std::to_string(options.responses.size() - 1) +
                                                     ", but the scene has " + std::to_string(pairs_.size()) + " contact pairs");
  for (std::size_t i = 0; i < pairs_.size(); ++i) {
    const ContactPairSpec& cp = scene_.contacts[i];
    const bool given = i < options.responses.size() && options.responses[i].force;
    if (!given && cp.plugin.empty()) continue;
    const std::string at = scene_.file + ": " + cp.path;
    if (given && !cp.plugin.empty())
      throw InputError(at + ".response", "the scene names a plug-in and the program gives a response of its own: one of them");
    if (!pairs_[i].collision)
      throw InputError(given ? scene_.file + ": effects" : at + ".response",
                       "a response for pair " + pairs_[i].label + " needs the \"contact\" effect, which the scene does not list");
    if (scene_.integrator != Integrator::symplectic_euler)
      throw InputError(scene_.file + ": time.integrator",
                       "a response of its own reports no stiffness, which the implicit step needs: use "
                       "\"symplectic_euler\"");
    if (pairs_[i].collision->projects())
      throw InputError(at + ".eliminator", std::string("eliminator \"") + cp.spec.eliminator +
                                               "\" applies no forces: a response of its own needs line or plane");
    pairs_[i].collision->set_response(given ? options.responses[i] : load_response_plugin(scene_, cp));
  }
}

void Simulation::build_effects(const SimulationOptions& options) {
  // With a peer engine the engine handles contact: the pairs stay (measured, recorded) without
  // the harness's detection and response.
  Scene built = scene_;
  if (options.engine) built.effects &= ~static_cast<unsigned>(kContact);
  EffectBuild b{built, world_, pairs_, kinematics_.pinned, kinematics_.drivers, kinematics_.loads, options.exact_detectors};
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
  stats_.implicit_iterations += stats_.implicit_last.iterations;
  ++stats_.implicit_solves;
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
    audit_->attach(ctx, scene_.integrator == Integrator::symplectic_euler && !corrects_);
    audit_->begin_step();
  }
  for (const auto& e : effects_) e->begin_step(w, ctx);
  const bool fused = scene_.integrator == Integrator::symplectic_euler && !corrects_;
  double total = 0.0;
  for (int s = 0; s < ctx.substeps; ++s) {
    const auto ts = Clock::now();
    std::fill(w.f.begin(), w.f.end(), Vec3::Zero());
    add_forces(ctx);
    if (fused && audit_) {
      audit_->integrate_and_book(w, ctx);
    } else if (fused) {
      symplectic_euler_step(w, ctx.h);
    } else {
      if (audit_) audit_->keep_velocities(w);
      integrate(ctx);
      after_integration(ctx);
      if (audit_) audit_->book(w, ctx);
    }
    total += us_since(ts);
  }
  for (const auto& e : effects_) e->end_step(w, ctx);
  if (audit_) audit_->end_step();
  next_forces_.clear();
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
    const double kinetic = kinetic_energy(), elastic = elastic_energy(), potential = potential_energy();
    ctx.f_spring = audit_->spring_forces();
    std::fill(w.f.begin(), w.f.end(), Vec3::Zero());
    add_forces(ctx);  // the external and springs' forces at the new state: the residual's scales
    audit_->engine_step(w, engine_v_prev_, scene_.dt, kinetic, elastic, potential);
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
  const bool external = external_ || !next_forces_.empty();
  if (external_ || user_forces_) std::fill(f_ext_.begin(), f_ext_.end(), Vec3::Zero());
  for (const auto& [i, f] : next_forces_) f_ext_[i] += f;
  bool joined = !external;
  auto join = [&] {
    const int n = w.num_nodes();
    const int T = threads_for(static_cast<std::size_t>(n));
#pragma omp parallel for num_threads(T) if(T > 1) schedule(static)
    for (int i = 0; i < n; ++i) w.f[i] += f_ext_[i];
    joined = true;
  };
  // Two threads or more: the contact's detection (from the positions alone: each pair and
  // direction a task) on some threads while the first effect (the springs) computes its forces on
  // the others; a thread joins them when its detection is done. The forces, their order and the
  // contacts are those of one thread; only the time differs: the shared pass is handed out in
  // chunks (less local than the pass's own split), so the overlap is taken when the last step's
  // detection took at least kOverlapShare of the time the first effect's forces took alone
  // (measured on the steps it runs alone).
  Effect* first = effects_.empty() ? nullptr : effects_.front().get();
  const bool can_overlap = ahead_ && first != ahead_ && threads() > 1;
  const Effect* done = nullptr;
  const bool worth = overlap_ == SimulationOptions::Overlap::always ||
                     (overlap_ == SimulationOptions::Overlap::automatic && alone_us_ > 0.0 &&
                      last_.detect_us >= kOverlapShare * alone_us_);
  if (can_overlap && worth && first->shareable(w)) {
    const int tasks = ahead_->ahead_tasks();
#pragma omp parallel num_threads(threads())
    {
#pragma omp for schedule(dynamic, 1) nowait
      for (int k = 0; k < tasks; ++k) ahead_->detect_ahead(w, k);
      first->add_forces_shared(w, s);
    }
    ahead_->ahead_done();
    done = first;
  } else if (can_overlap) {
    const auto t0 = Clock::now();
    first->add_forces(w, s);
    alone_us_ = us_since(t0);
    done = first;
  }
  for (const auto& e : effects_) {
    if (e.get() == done) continue;
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

void Simulation::restore(const Points& x, const Points& v, int step) {
  std::copy(x.begin(), x.end(), world_.x.begin());
  std::copy(v.begin(), v.end(), world_.v.begin());
  step_index_ = step;
}

double Simulation::kinetic_energy() const { return harness::kinetic_energy(world_); }

double Simulation::potential_energy() const {
  double e = 0.0;
  for (const auto& f : effects_) e += f->energy(world_);
  return e;
}

void Simulation::book_kinetic_change(double dE) {
  if (audit_) audit_->book_external(dE);
}

void Simulation::add_next_force(int i, const Vec3& f) {
  if (!user_forces_) throw std::logic_error("add_next_force: the simulation was built without SimulationOptions::user_forces");
  if (i < 0 || i >= world_.num_nodes()) throw std::out_of_range("add_next_force: node out of range");
  next_forces_.emplace_back(i, f);
}

void Simulation::reset_energy() {
  if (audit_) audit_->reset(kinetic_energy(), elastic_energy(), potential_energy());
}

const EnergyLedger& Simulation::energy_booked() const {
  static const EnergyLedger none;
  return audit_ ? audit_->ledger() : none;
}

// Evaluating the pending energy swaps the positions with the step's force point and back: the
// world is the simulation's own (never a const object), its bits unchanged.
const EnergyLedger& Simulation::energy() const {
  if (audit_ && audit_->elastic_pending())
    audit_->complete(const_cast<World&>(world_), [this](const World& w) { return elastic_energy(w); });
  return energy_booked();
}

double Simulation::residual() const {
  return audit_ ? audit_->residual() : std::numeric_limits<double>::quiet_NaN();
}

double Simulation::elastic_energy() const { return elastic_energy(world_); }

double Simulation::elastic_energy(const World& w) const {
  double e = 0.0;
  for (const auto& f : effects_)
    if (f->category() == EffectCategory::elastic) e += f->energy(w);
  return e;
}

double Simulation::critical_dt() const {
  std::vector<Vec3> rows;
  return harness::critical_dt(world_, effects_, rows);
}

}  // namespace harness
