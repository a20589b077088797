#include "core/simulation.hpp"

#include "core/mesh.hpp"
#include "core/parallel.hpp"
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

using Clock = std::chrono::steady_clock;
double us_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::micro>(Clock::now() - t0).count();
}

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
  // Rest positions are not kept separately: selections are evaluated at build time, before
  // any step, when x holds the rest positions.
  for (int i = b.begin; i < b.end; ++i) {
    const Vec3& p = w.x[i];
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

Simulation::Simulation(const Scene& scene) : scene_(scene) {
  const Scene& sc = scene_;
  World& w = world;
  // Generate every body, then lay the nodes out in one set of arrays.
  for (const BodySpec& bs : sc.bodies) {
    ShapeModel model = generate(sc, bs);
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
    for (const Edge& e : model.springs) {
      w.springs.ends.push_back({b.begin + e[0], b.begin + e[1]});
      w.springs.rest.push_back((model.nodes[e[1]] - model.nodes[e[0]]).norm());
      w.springs.body.push_back(body_index);
    }
    b.spring_end = static_cast<int>(w.springs.size());
    for (std::size_t i = 0; i < model.nodes.size(); ++i) {
      w.x.push_back(model.nodes[i]);
      w.v.push_back(bs.velocity);
      const double m = bs.material.density * model.node_volume[i];
      w.m.push_back(m);
    }
    w.body_law.push_back({bs.material.law, bs.material.stiffness, bs.material.nonlinearity});
    w.bodies.push_back(std::move(b));
  }
  const int n = w.num_nodes();
  for (int i = 0; i < n; ++i) {
    if (!(w.m[i] > 0.0) || !std::isfinite(w.m[i]))
      throw InputError(sc.file + ": bodies", "a node has no positive mass (check density and shape)");
    w.inv_m.push_back(1.0 / w.m[i]);
  }
  w.f.assign(n, Vec3::Zero());
  w.kinematic.assign(n, 0);
  w.kin_v.assign(n, Vec3::Zero());
  pinned_.assign(n, 0);
  driven_now_.assign(n, 0);

  // Selections are checked whether or not their effect is listed: a bad scene is bad input.
  for (std::size_t bi = 0; bi < sc.bodies.size(); ++bi) {
    const BodySpec& bs = sc.bodies[bi];
    for (const Selection& sel : bs.pins) {
      const auto nodes = select_nodes(w, static_cast<int>(bi), sel);
      if (nodes.empty()) throw InputError(sc.file + ": " + sel.path, "selection selects no node");
      if (sc.has(kPins))
        for (int i : nodes) pinned_[i] = 1;
    }
    for (std::size_t d = 0; d < bs.drivers.size(); ++d) {
      const DriverSpec& ds = bs.drivers[d];
      auto nodes = select_nodes(w, static_cast<int>(bi), ds.select);
      if (nodes.empty())
        throw InputError(sc.file + ": " + bs.path + ".drivers." + std::to_string(d) + ".select",
                         "selection selects no node");
      if (sc.has(kDrivers)) driver_nodes_.push_back({std::move(nodes), ds.velocity, ds.from_step, ds.to_step});
    }
  }
  pins_ = sc.has(kPins);
  drivers_ = sc.has(kDrivers);
  for (int i = 0; i < n; ++i) {
    w.kinematic[i] = pinned_[i];
    if (pinned_[i]) w.v[i] = Vec3::Zero();
  }

  if (sc.has(kSprings)) forces_.push_back(make_springs_effect());
  if (sc.has(kDamping)) forces_.push_back(make_damping_effect());
  if (sc.has(kGravity)) forces_.push_back(make_gravity_effect(sc.gravity));
  if (sc.has(kPressure)) {
    std::vector<std::pair<int, PressureSpec>> pb;
    for (std::size_t bi = 0; bi < sc.bodies.size(); ++bi)
      if (sc.bodies[bi].pressure.present) pb.emplace_back(static_cast<int>(bi), sc.bodies[bi].pressure);
    if (!pb.empty()) forces_.push_back(make_pressure_effect(std::move(pb)));
  }

  for (const ContactPairSpec& cp : sc.contacts) {
    PairSlot slot;
    slot.spec = cp.spec;
    slot.spec.host = w.find_body(cp.host);
    slot.spec.guest = w.find_body(cp.guest);
    slot.label = cp.host + "/" + cp.guest;
    if (sc.has(kContact)) {
      try {
        slot.collision = std::make_unique<Collision>(w, slot.spec);
      } catch (const std::invalid_argument& e) {
        throw InputError(sc.file + ": " + cp.path, e.what());
      }
    }
    pairs.push_back(std::move(slot));
  }

  // Stability guard of the explicit integrator (at rest); implicit Euler needs none.
  dt_crit = critical_dt(w, crit_rows_);
  dt_crit_min = dt_crit;
  if (sc.integrator == Integrator::symplectic_euler && std::isfinite(dt_crit) && sc.dt > 0.9 * dt_crit) {
    char buf[256];
    if (sc.guard == Guard::refuse) {
      std::snprintf(buf, sizeof buf,
                    "dt = %.6g s exceeds 0.9 dt_crit = %.6g s (dt_crit = %.6g s, Gershgorin bound); "
                    "lower dt or set time.guard to \"substep\"",
                    sc.dt, 0.9 * dt_crit, dt_crit);
      throw InputError(sc.file + ": time.dt", buf);
    }
    const double ratio = sc.dt / (0.9 * dt_crit);
    if (ratio > 1e6) throw InputError(sc.file + ": time.dt", "dt needs more than 1e6 substeps");
    substeps = static_cast<int>(std::ceil(ratio));
  }
  max_substeps = substeps;
  dt_crit_last_ = dt_crit;
}

void Simulation::guard_check() {
  const double measured = critical_dt(world, crit_rows_);
  // A stiffening law keeps shrinking dt_crit during the coming step: extrapolate the trend
  // since the last check (geometrically) so that the substeps are sized for the step's end.
  double d = measured;
  if (std::isfinite(dt_crit_last_) && dt_crit_last_ > measured && measured > 0.0)
    d = measured * (measured / dt_crit_last_);
  dt_crit_last_ = measured;
  dt_crit_min = std::min(dt_crit_min, d);
  if (scene_.integrator != Integrator::symplectic_euler || !std::isfinite(d)) return;
  const double ratio = scene_.dt / (0.9 * d);
  if (scene_.guard == Guard::substep) {
    substeps = std::max(1, static_cast<int>(std::ceil(std::min(ratio, 1e6))));
    max_substeps = std::max(max_substeps, substeps);
  } else if (ratio > 1.0) {
    ++guard_violations;
  }
}

std::vector<std::string> Simulation::effects_simulated() const {
  std::vector<std::string> out;
  for (const auto& [bit, name] : effect_names())
    if (scene_.has(bit)) out.push_back(name);
  return out;
}

void Simulation::update_kinematics(int step) {
  if (!drivers_) return;
  World& w = world;
  // Active drivers first (a later driver wins where two overlap); then the nodes no active
  // driver moves any more are released with their last velocity. Releasing inside the loop
  // would let an inactive driver free nodes that another driver is moving.
  for (const DriverNodes& d : driver_nodes_)
    for (int i : d.nodes) driven_now_[i] = 0;
  for (const DriverNodes& d : driver_nodes_) {
    if (!(step >= d.from_step && (d.to_step < 0 || step <= d.to_step))) continue;
    for (int i : d.nodes) {
      if (pinned_[i]) continue;  // a pin wins over a driver
      driven_now_[i] = 1;
      w.kinematic[i] = 2;
      w.kin_v[i] = d.velocity;
      w.v[i] = d.velocity;
    }
  }
  for (const DriverNodes& d : driver_nodes_)
    for (int i : d.nodes)
      if (!driven_now_[i] && w.kinematic[i] == 2) {
        w.kinematic[i] = 0;  // released: keeps its last velocity
        w.kin_v[i] = Vec3::Zero();
      }
}

void Simulation::integrate(double h) {
  World& w = world;
  const int n = w.num_nodes();
  // Per node, independent: parallel (core/parallel.hpp) with the same result for any thread count.
#pragma omp parallel for num_threads(threads_for(static_cast<std::size_t>(n))) schedule(dynamic, 8192)
  for (int i = 0; i < n; ++i) {
    switch (w.kinematic[i]) {
      case 0:
        w.v[i] += (h * w.inv_m[i]) * w.f[i];
        w.x[i] += h * w.v[i];
        break;
      case 1:  // pinned: untouched, bit-exact
        break;
      default:  // driven
        w.x[i] += h * w.kin_v[i];
        break;
    }
  }
}

void Simulation::step() {
  const auto t0 = Clock::now();
  ++step_index;
  World& w = world;
  // The guard re-evaluates dt_crit every kGuardEvery steps, and every step once dt per substep
  // is within a factor 2 of the limit (stiffening laws can halve dt_crit within ten steps).
  if (scene_.has(kSprings) && step_index > 1 &&
      ((step_index - 1) % kGuardEvery == 0 || scene_.dt / substeps > 0.45 * dt_crit_last_))
    guard_check();
  const double h = scene_.dt / substeps;
  update_kinematics(step_index);
  for (PairSlot& p : pairs) p.contacts = 0, p.t_detect_us = p.t_eliminate_us = p.force = 0.0;
  StepInfo info{step_index, h};
  double physics = 0.0;
  for (int s = 0; s < substeps; ++s) {
    const auto tp = Clock::now();
    std::fill(w.f.begin(), w.f.end(), Vec3::Zero());
    for (auto& e : forces_) e->apply(w, info);
    physics += us_since(tp);
    for (PairSlot& p : pairs) {
      if (!p.collision) continue;
      const PairStepStats st = p.collision->step(w, h);
      p.contacts += st.contacts;
      p.t_detect_us += st.t_detect_us;
      p.t_eliminate_us += st.t_eliminate_us;
      p.force = std::max(p.force, st.force);
    }
    const auto ti = Clock::now();
    if (scene_.integrator == Integrator::implicit_euler) {
      implicit_last = implicit_.step(w, h, scene_.has(kSprings), scene_.has(kDamping));
      implicit_max_iterations = std::max(implicit_max_iterations, implicit_last.iterations);
      if (!implicit_last.converged) ++implicit_unconverged;
    } else {
      integrate(h);
    }
    physics += us_since(ti);
  }
  if (substeps > 1)
    for (PairSlot& p : pairs) p.contacts = (p.contacts + substeps - 1) / substeps;
  time = step_index * scene_.dt;
  last.physics_us = physics;
  last.detect_us = last.eliminate_us = 0.0;
  for (const PairSlot& p : pairs) last.detect_us += p.t_detect_us, last.eliminate_us += p.t_eliminate_us;
  last.step_us = us_since(t0);
}

double Simulation::kinetic_energy() const {
  double e = 0.0;
  for (int i = 0; i < world.num_nodes(); ++i) e += 0.5 * world.m[i] * world.v[i].squaredNorm();
  return e;
}

double Simulation::potential_energy() const {
  double e = 0.0;
  for (const auto& f : forces_) e += f->energy(world);
  return e;
}

double critical_dt(const World& w, std::vector<Vec3>& rows) {
  const int n = w.num_nodes();
  if (w.springs.size() == 0) return std::numeric_limits<double>::infinity();
  rows.assign(static_cast<std::size_t>(n), Vec3::Zero());
  add_spring_stiffness_rows(w, rows);
  double lam = 0.0;
  for (int i = 0; i < n; ++i)
    if (w.kinematic[i] == 0) lam = std::max(lam, rows[i].maxCoeff() * w.inv_m[i]);
  if (lam <= 0.0) return std::numeric_limits<double>::infinity();
  return 2.0 / std::sqrt(lam);
}

double critical_dt(const World& w) {
  std::vector<Vec3> rows;
  return critical_dt(w, rows);
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
