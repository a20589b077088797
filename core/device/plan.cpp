#include "core/device/plan.hpp"

#include "core/collision/detectors/triangles.hpp"
#include "core/collision/detectors/voxel.hpp"
#include "core/collision/detectors/voxel_exact.hpp"
#include "core/collision/responses/force_rule.hpp"
#include "core/device/device_step.hpp"
#include "core/spring_forces.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>

namespace harness {

namespace {

[[noreturn]] void refuse(const Scene& s, const std::string& key, const std::string& what) {
  throw InputError(s.file + ": " + key, what + " (not on a device: run it without --device)");
}

}  // namespace

void check_device_support(const Simulation& sim) {
  const Scene& s = sim.scene();
  if (sim.engine()) refuse(s, "--engine", "a peer engine");
  if (s.integrator != Integrator::symplectic_euler) refuse(s, "time.integrator", "the implicit integrator");
  if (sim.stats().stability.substeps > 1)
    refuse(s, "time.dt", "a dt the guard substeps (" + std::to_string(sim.stats().stability.substeps) + " substeps)");
  const World& w = sim.world();  // one law per node: every spring within one body (SpringGather::mixed)
  for (std::size_t k = 0; k < w.springs.size(); ++k) {
    const Body& b = w.bodies[w.springs.body[k]];
    for (int e : w.springs.ends[k])
      if (e < b.begin || e >= b.end) refuse(s, "bodies", "a spring whose ends lie in different bodies");
  }
  if (s.has(kBulk))
    for (const BodySpec& b : s.bodies)
      if (b.material.bulk_modulus > 0.0) refuse(s, b.path + ".material.bulk_modulus", "the bulk effect");
  if (!s.has(kContact)) return;
  for (std::size_t i = 0; i < s.contacts.size(); ++i) {
    const ContactSpec& c = s.contacts[i].spec;
    const std::string& p = s.contacts[i].path;
    const DetectorDef* det = find_detector(c.detector);
    if (!det || det->device < 0) refuse(s, p + ".detector", "detector \"" + c.detector + "\"");
    // voxel_exact's pushes with the penalty force are the contact point's whatever the rule (line or
    // plane: penalty_depth); with a constant force only the line rule is on a device.
    if (eliminator_of(c).device < 0 ||
        (c.detector == "voxel_exact" && c.eliminator != "line" && !force_rule_of(c).depth))
      refuse(s, p + ".eliminator", std::string("eliminator \"") + c.eliminator + "\" with detector \"" +
                                       c.detector + "\"");
    if (force_rule_of(c).device < 0) refuse(s, p + ".force", "the force rule \"" + c.force_rule + "\"");
    if (c.orient != Orient::paper) refuse(s, p + ".orient", "an orientation other than \"paper\"");
    if (c.damping > 0.0) refuse(s, p + ".damping", "the contact damping variant");
    const Collision* col = sim.pairs()[i].collision.get();
    if (col && col->has_response()) refuse(s, p + ".response", "a response of its own (" + col->response_name() + ")");
  }
}

namespace {
int keys_max = dev::kKeysMax;
}
void set_device_keys_max(int n) { keys_max = n; }

namespace dev {

long long grid_capacity(const GridState& g) {
  // The full region of a host twice as large per axis: a growing host (an inflating implant)
  // rebuilds within it.
  double count = 1.0;
  for (int a = 0; a < 3; ++a) count *= 2.0 * (std::floor(2.0 * g.built_h[a] / g.voxel) + 2.0 + g.margin);
  return static_cast<long long>(std::min(count, static_cast<double>(kMaxVoxels)));
}

namespace {

void surface_of(const World& w, int body, DirPlan& d) {
  const Body& b = w.bodies[body];
  d.faces.clear();
  for (const Tri& t : b.faces) d.faces.insert(d.faces.end(), t.begin(), t.end());
  d.vf_start = b.vf_start;
  d.vf_faces = b.vf_faces;
  if (d.vf_start.empty()) d.vf_start.assign(static_cast<std::size_t>(b.n_surface) + 1, 0);
  d.adjacent = edge_adjacency(b.faces);  // the face across each edge (voxel_exact.cpp's adjacent_)
}

DirPlan dir_plan(const World& w, const ContactSpec& spec, int host, int guest, const CollisionDetector& det) {
  DirPlan d;
  d.host = host, d.guest = guest;
  const Body& hb = w.bodies[host];
  const Body& gb = w.bodies[guest];
  d.host_begin = hb.begin, d.host_size = hb.size(), d.host_surface = hb.n_surface;
  d.guest_begin = gb.begin, d.guest_size = gb.size();
  const DetectorDef* det_def = find_detector(spec.detector);
  if (!det_def || det_def->device < 0) throw std::logic_error("device plan: a detector without a kernel");
  d.detector = det_def->device;
  d.eliminator = eliminator_of(spec).device;
  // The rule's device kernel and its one parameter (F of kForceConstant, k of kForcePenalty).
  const ForceRuleDef& rule = force_rule_of(spec);
  if (rule.device < 0 || spec.force_parameters.size() != 1) throw std::logic_error("device plan: a force rule without a kernel");
  d.force_rule = rule.device;
  d.force = d.stiffness = spec.force_parameters[0];
  d.invert = spec.invert_push;
  const Initializer* init = nullptr;
  if (const auto* v = dynamic_cast<const VoxelDetector*>(&det)) init = &v->initializer();
  if (const auto* v = dynamic_cast<const VoxelExactDetector*>(&det)) init = &v->initializer();
  if (!init) throw std::logic_error("device plan: a detector without the paper's grid");
  const bool surface = d.detector == kDetVoxelExact || spec.host_nodes == HostNodes::surface;
  d.listed_begin = hb.begin;
  d.listed = surface ? hb.n_surface : hb.size();
  d.keys = d.listed <= std::min(keys_max, kKeysMax);
  GridState& g = d.grid;
  g.voxel = init->voxel_size();
  g.region = spec.region == Region::full ? kRegionFull : spec.region == Region::overlap ? kRegionOverlap : kRegionHalf;
  g.margin = spec.margin;
  for (int a = 0; a < 3; ++a) g.built_h[a] = init->built_half_extents()[a];
  g.half_axis = init->half_axis(), g.half_sign = init->half_sign();
  for (int a = 0; a < 3; ++a) {  // Initializer::build's region, as the CPU built it at rest
    g.n[a] = static_cast<int>(std::floor(g.built_h[a] / g.voxel) + 2.0);
    g.cap_lo[a] = -(g.n[a] + g.margin);
    g.cap_dims[a] = 2 * (g.n[a] + g.margin);
    g.lo[a] = g.cap_lo[a], g.dims[a] = g.cap_dims[a];
  }
  if (g.half_axis >= 0) {
    const int ax = g.half_axis;
    g.dims[ax] = g.n[ax] + 2 * g.margin;
    g.lo[ax] = g.half_sign > 0 ? -g.margin : -g.n[ax] - g.margin;
  }
  g.rebuilds = 0;
  g.capacity = grid_capacity(g);
  surface_of(w, host, d);  // voxel_exact's narrow phase; the line and plane rules' outward hints
  return d;
}

}  // namespace

namespace {

// The state and the per-node constants (positions, velocities, masses, kinematic flags, mass damping).
void plan_state(DevicePlan& P, const Simulation& sim) {
  const World& w = sim.world();
  const int n = w.num_nodes();
  P.n = n;
  P.dt = sim.scene().dt;
  P.step0 = sim.step_index();
  P.x.resize(3 * static_cast<std::size_t>(n));
  P.v.resize(P.x.size());
  P.kin_v.resize(P.x.size());
  for (int i = 0; i < n; ++i)
    for (int k = 0; k < 3; ++k) P.x[3 * i + k] = w.x[i][k], P.v[3 * i + k] = w.v[i][k], P.kin_v[3 * i + k] = w.kin_v[i][k];
  P.m = w.m;
  P.inv_m = w.inv_m;
  P.kind.resize(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) P.kind[i] = static_cast<unsigned char>(w.kinematic[i]);
  P.mass_damping.assign(static_cast<std::size_t>(n), 0.0);
  for (const Body& b : w.bodies)
    for (int i = b.begin; i < b.end; ++i) P.mass_damping[i] = b.material.mass_damping;
}

// Each node's springs as half-edges (upper ones first, then the lower ones' partners) and each
// body's law.
void plan_springs(DevicePlan& P, const World& w) {
  const int n = w.num_nodes();
  SpringGather g;
  g.build(w);
  P.he_start.assign(1, 0);
  for (int i = 0; i < n; ++i) {
    for (int h = g.up_start[i]; h < g.up_start[i + 1]; ++h)
      P.he_other.push_back(g.up_other[h]), P.he_rest.push_back(g.up_rest[h]), P.he_stiff.push_back(g.up_stiff[h]);
    P.he_split.push_back(static_cast<int>(P.he_other.size()));
    for (int t = g.lo_start[i]; t < g.lo_start[i + 1]; ++t) {
      const int h = g.lo_slot[t];  // the spring's upper half-edge
      P.he_other.push_back(g.up_self[h]), P.he_rest.push_back(g.up_rest[h]), P.he_stiff.push_back(g.up_stiff[h]);
    }
    P.he_start.push_back(static_cast<int>(P.he_other.size()));
  }
  P.node_law.assign(static_cast<std::size_t>(n), 0);
  for (std::size_t b = 0; b < w.bodies.size(); ++b) {
    const BodyLaw& L = w.body_law[b];
    P.laws.push_back(Law{static_cast<int>(L.kind), L.beta, 1.0 / L.beta, w.bodies[b].material.damping});
    for (int i = w.bodies[b].begin; i < w.bodies[b].end; ++i) P.node_law[i] = static_cast<int>(b);
  }
  if (P.laws.empty()) P.laws.push_back(Law{0, 0.0, 0.0, 0.0});
}

// The pressured shells' faces and each node's incident faces; false when no body is pressured.
bool plan_pressure(DevicePlan& P, const Scene& s, const World& w) {
  const int n = w.num_nodes();
  bool pressure = false;
  std::vector<std::vector<int>> incident(static_cast<std::size_t>(n));
  for (std::size_t b = 0; b < s.bodies.size(); ++b) {
    const PressureSpec& ps = s.bodies[b].pressure;
    if (!ps.present) continue;
    pressure = true;
    const int pi = static_cast<int>(P.p_from.size());
    P.p_from.push_back(ps.from), P.p_to.push_back(ps.to), P.p_ramp.push_back(ps.ramp_steps);
    const Body& body = w.bodies[b];
    for (const Tri& t : body.faces) {
      const int f = static_cast<int>(P.face_p.size());
      for (int k = 0; k < 3; ++k) P.face_v.push_back(body.begin + t[k]);
      P.face_p.push_back(pi);
      for (int k = 0; k < 3; ++k) incident[body.begin + t[k]].push_back(f);
    }
  }
  P.pf_start.assign(1, 0);
  for (const auto& l : incident) {
    P.pf_face.insert(P.pf_face.end(), l.begin(), l.end());
    P.pf_start.push_back(static_cast<int>(P.pf_face.size()));
  }
  return pressure;
}

// The loads and each node's loads.
void plan_loads(DevicePlan& P, const Kinematics& kin, int n) {
  std::vector<std::vector<int>> on(static_cast<std::size_t>(n));
  for (std::size_t l = 0; l < kin.loads.size(); ++l) {
    const LoadNodes& L = kin.loads[l];
    for (int k = 0; k < 3; ++k) P.ld_force.push_back(L.force[k]);
    P.ld_count.push_back(static_cast<int>(L.nodes.size()));
    P.ld_ramp.push_back(L.ramp_steps);
    for (int i : L.nodes) on[i].push_back(static_cast<int>(l));
  }
  P.ld_start.assign(1, 0);
  for (const auto& l : on) {
    P.ld_load.insert(P.ld_load.end(), l.begin(), l.end());
    P.ld_start.push_back(static_cast<int>(P.ld_load.size()));
  }
}

// The drivers and the driven nodes' drivers (in node order).
void plan_drivers(DevicePlan& P, const Kinematics& kin) {
  std::map<int, std::vector<int>> by_node;
  for (std::size_t d = 0; d < kin.drivers.size(); ++d) {
    const DriverNodes& D = kin.drivers[d];
    P.dr_from.push_back(D.from_step), P.dr_to.push_back(D.to_step);
    for (int k = 0; k < 3; ++k) P.dr_vel.push_back(D.velocity[k]);
    for (int i : D.nodes) {
      auto& v = by_node[i];
      if (v.empty() || v.back() != static_cast<int>(d)) v.push_back(static_cast<int>(d));
    }
  }
  P.dr_start.assign(1, 0);
  for (const auto& [node, ds] : by_node) {
    P.dr_node.push_back(node);
    P.dr_driver.insert(P.dr_driver.end(), ds.begin(), ds.end());
    P.dr_start.push_back(static_cast<int>(P.dr_driver.size()));
  }
}

// Each contact pair's plan, both ways where it is two-sided.
void plan_pairs(DevicePlan& P, const Simulation& sim) {
  const World& w = sim.world();
  for (const Pair& pr : sim.pairs()) {
    const Collision& col = *pr.collision;
    const ContactSpec& c = col.spec();
    PairPlan pp;
    pp.fwd = dir_plan(w, c, c.host, c.guest, col.detector());
    pp.two_sided = c.two_sided;
    if (c.two_sided) pp.rev = dir_plan(w, c, c.guest, c.host, *col.reverse_detector());
    pp.a_begin = w.bodies[c.host].begin, pp.a_end = w.bodies[c.host].end;
    pp.b_begin = w.bodies[c.guest].begin, pp.b_end = w.bodies[c.guest].end;
    P.pairs.push_back(std::move(pp));
  }
}

}  // namespace

DevicePlan make_plan(const Simulation& sim) {
  check_device_support(sim);
  const World& w = sim.world();
  const Scene& s = sim.scene();
  DevicePlan P;
  plan_state(P, sim);
  plan_springs(P, w);
  P.springs = s.has(kSprings);
  P.dashpots = s.has(kDamping);
  P.damping = s.has(kDamping);
  P.gravity = s.has(kGravity);
  for (int k = 0; k < 3; ++k) P.g[k] = s.gravity[k];
  const bool pressure = s.has(kPressure) && plan_pressure(P, s, w);
  const Kinematics& kin = sim.kinematics();
  const bool loads = s.has(kLoads) && !kin.loads.empty();
  if (loads) plan_loads(P, kin, w.num_nodes());
  P.external = P.gravity || pressure || loads;
  if (s.has(kDrivers) && !kin.drivers.empty()) plan_drivers(P, kin);
  if (s.has(kContact)) plan_pairs(P, sim);
  return P;
}

}  // namespace dev
}  // namespace harness
