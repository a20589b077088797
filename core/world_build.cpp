#include "core/world_build.hpp"

#include "core/mesh.hpp"
#include "core/node_order.hpp"
#include "core/shapes/shapes.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <stdexcept>

namespace harness {

namespace {

// The body's model from its shape (shapes/; meshes read by mesh.hpp), errors named by key path.
ShapeModel generate(const Scene& sc, const BodySpec& b) {
  const ShapeSpec& s = b.shape;
  const Fill fill = s.volume_fill ? Fill::volume : Fill::shell;
  try {
    switch (s.type) {
      case ShapeType::box: return make_box(s.min, s.max, s.cells, s.alternating_diagonals);
      case ShapeType::sphere: return make_sphere(s.center, s.radius, s.subdivisions, fill);
      case ShapeType::ellipsoid: return make_ellipsoid(s.center, s.radii, s.subdivisions, fill);
      case ShapeType::cylinder: return make_cylinder(s.center, s.axis, s.radius, s.length, s.segments, s.rings, fill);
      case ShapeType::mesh: break;
    }
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
void append_body(World& w, const BodySpec& bs, ShapeModel&& model, const WorldBuild& build) {
  const NodeOrder order = build.order;
  Body b;
  // The layout's permutation, perm[new] = the scene's index: an arbitrary numbering first when
  // asked for (benches, tests: each body's surface and interior shuffled apart), then the order.
  std::vector<int> perm(model.nodes.size());
  std::iota(perm.begin(), perm.end(), 0);
  if (build.shuffle_seed != 0) {
    std::mt19937_64 g(build.shuffle_seed);
    const auto ns = static_cast<std::ptrdiff_t>(std::clamp(model.n_surface, 0, static_cast<int>(perm.size())));
    std::shuffle(perm.begin(), perm.begin() + ns, g);
    std::shuffle(perm.begin() + ns, perm.end(), g);
    apply_node_permutation(model, perm);
  }
  if (order != NodeOrder::scene) {
    const std::vector<int> p = node_permutation(model, order);
    apply_node_permutation(model, p);
    std::vector<int> total(p.size());
    for (std::size_t k = 0; k < p.size(); ++k) total[k] = perm[static_cast<std::size_t>(p[k])];
    perm = std::move(total);
  }
  bool identity = true;
  for (std::size_t k = 0; k < perm.size(); ++k) identity = identity && perm[k] == static_cast<int>(k);
  if (!identity) {
    b.node_of_scene.assign(perm.size(), 0);
    for (std::size_t k = 0; k < perm.size(); ++k) b.node_of_scene[static_cast<std::size_t>(perm[k])] = static_cast<int>(k);
    b.scene_node = std::move(perm);
  }
  b.name = bs.name;
  b.begin = w.num_nodes();
  b.end = b.begin + static_cast<int>(model.nodes.size());
  b.n_surface = model.n_surface;
  b.faces = std::move(model.faces);
  b.cells = std::move(model.cells);
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
  points_bounds(model.nodes, 0, static_cast<int>(model.nodes.size()), b.rest_min, b.rest_max);
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

World build_world(const Scene& scene, const WorldBuild& build) {
  World w;
  w.node_order = build.order;
  for (const BodySpec& bs : scene.bodies) append_body(w, bs, generate(scene, bs), build);
  const int n = w.num_nodes();
  for (int i = 0; i < n; ++i) {
    if (!(w.m[i] > 0.0) || !std::isfinite(w.m[i]))
      throw InputError(scene.file + ": bodies", "a node has no positive mass (check density and shape)");
    w.inv_m.push_back(1.0 / w.m[i]);
  }
  w.x0 = w.x;
  w.f.assign(n, Vec3::Zero());
  w.kinematic.assign(n, Kinematic::free);
  w.kin_v.assign(n, Vec3::Zero());
  return w;
}

// Selections are resolved and checked whether or not their effect is listed: a bad scene is
// bad input either way.
Kinematics resolve_kinematics(const Scene& scene, const World& world) {
  Kinematics k;
  for (std::size_t bi = 0; bi < scene.bodies.size(); ++bi) {
    const BodySpec& bs = scene.bodies[bi];
    for (const Selection& sel : bs.pins) {
      const auto nodes = select_nodes(world, static_cast<int>(bi), sel);
      if (nodes.empty()) throw InputError(scene.file + ": " + sel.path, "selection selects no node");
      k.pinned.insert(k.pinned.end(), nodes.begin(), nodes.end());
    }
    for (std::size_t d = 0; d < bs.drivers.size(); ++d) {
      const DriverSpec& ds = bs.drivers[d];
      auto nodes = select_nodes(world, static_cast<int>(bi), ds.select);
      if (nodes.empty())
        throw InputError(scene.file + ": " + bs.path + ".drivers." + std::to_string(d) + ".select",
                         "selection selects no node");
      k.drivers.push_back({std::move(nodes), ds.velocity, ds.from_step, ds.to_step});
    }
    for (std::size_t l = 0; l < bs.loads.size(); ++l) {
      const LoadSpec& ls = bs.loads[l];
      auto nodes = select_nodes(world, static_cast<int>(bi), ls.select);
      if (nodes.empty())
        throw InputError(scene.file + ": " + bs.path + ".loads." + std::to_string(l) + ".select",
                         "selection selects no node");
      k.loads.push_back({std::move(nodes), ls.force, ls.ramp_steps});
    }
  }
  return k;
}

}  // namespace harness
