// The simulated state: every body's nodes in one set of contiguous arrays (hot, per step),
// with per-body topology kept apart (cold). Node indices in these arrays are "global";
// a body owns the global range [begin, end).
#pragma once

#include "core/springs.hpp"
#include "core/types.hpp"

#include <string>
#include <vector>

namespace harness {

// A body's material. No default values of its own (zero until made): the scene loader fills it
// from the key table's rows "material.*", and a body built by hand starts from
// material_defaults() (core/scene/scene.hpp).
struct Material {
  double density = 0.0;    // kg/m^3
  double stiffness = 0.0;  // N/m, per spring (when youngs_modulus is 0)
  double youngs_modulus = 0.0;  // Pa; > 0: every spring's stiffness from it (elastic_map.hpp)
  double thickness = 0.0;       // m, of a shell (with youngs_modulus)
  SpringLawKind law = SpringLawKind::linear;
  double nonlinearity = 0.0;  // beta >= 0
  double damping = 0.0;       // N s/m, dashpot along each spring (effect "damping")
  double mass_damping = 0.0;  // 1/s, global damping force -mass_damping * m * v (effect "damping")
  double bulk_modulus = 0.0;  // Pa, a box cell's resistance to a change of its volume (effect "bulk")
};

struct Body {
  std::string name;
  int begin = 0;      // first global node index
  int end = 0;        // one past the last
  int n_surface = 0;  // the first n_surface nodes of the body are its surface vertices
  // Closed, outward-oriented triangles over body-local node indices 0..n_surface-1.
  std::vector<Tri> faces;
  // A box lattice's cells over body-local node indices (empty for other shapes): effect "bulk".
  std::vector<Cell> cells;
  // Body-local vertex -> incident faces (CSR), for vertex normals on demand.
  std::vector<int> vf_start, vf_faces;
  int spring_begin = 0, spring_end = 0;  // range in World::springs
  Material material;
  Vec3 rest_min = Vec3::Zero(), rest_max = Vec3::Zero();  // rest bounding box
  double volume = 0.0;                                    // rest enclosed volume, m^3

  // The node order (node_order.hpp): scene_node[i] is the scene's body-local index of the node at
  // body-local index i, node_of_scene its inverse; both empty when the order is the scene's own.
  // Outputs that name or list nodes use the scene's numbering.
  std::vector<int> scene_node, node_of_scene;

  int size() const { return end - begin; }
  int surface_node(int s) const { return begin + s; }  // global index of surface vertex s
  // The scene's body-local index of body-local node i, and the body-local node of scene index s.
  int scene_index(int i) const { return scene_node.empty() ? i : scene_node[static_cast<std::size_t>(i)]; }
  int local_of_scene(int s) const { return node_of_scene.empty() ? s : node_of_scene[static_cast<std::size_t>(s)]; }
};

// The law all springs of a body follow; each spring has its own stiffness (Springs::k).
struct BodyLaw {
  SpringLawKind kind = SpringLawKind::linear;
  double beta = 0.0;  // nonlinearity, >= 0
  SpringLaw with(double k) const { return SpringLaw{kind, k, beta}; }
};

struct Springs {
  std::vector<Edge> ends;      // global node indices
  std::vector<double> rest;    // rest length L0, m
  std::vector<double> k;       // stiffness, N/m (from material.stiffness or youngs_modulus)
  std::vector<int> body;       // owning body index (law and damping come from its material)
  std::size_t size() const { return ends.size(); }
};

// How a node moves: integrated (free), held fixed (pinned, effect "pins"), or moved with a
// prescribed velocity kin_v (driven, effect "drivers").
enum class Kinematic : std::uint8_t { free, pinned, driven };

// How a world's nodes are laid out in its arrays (node_order.hpp): the scene's own numbering, or
// an order by locality.
enum class NodeOrder {
  scene,   // as generated or read (the shape's own numbering)
  morton,  // by the Morton (Z-order) code of the rest position over the body's box
  rcm,     // reverse Cuthill-McKee over the springs (breadth-first from a peripheral node)
};
const char* node_order_name(NodeOrder o);

struct World {
  Points x;   // positions, m
  Points x0;  // rest positions, m (as generated; selections and displacements refer to them)
  Points v;   // velocities, m/s
  Points f;   // force accumulator, N (cleared each step)
  std::vector<double> m;      // lumped masses, kg
  std::vector<double> inv_m;  // 1/m
  // Kinematic nodes (pins, drivers) are moved with kin_v instead of integrated.
  std::vector<Kinematic> kinematic;
  Points kin_v;
  std::vector<Body> bodies;
  std::vector<BodyLaw> body_law;  // per body
  Springs springs;
  NodeOrder node_order = NodeOrder::scene;  // the layout it was built in (Body::scene_node per body)

  int num_nodes() const { return static_cast<int>(x.size()); }
  bool is_free(int i) const { return kinematic[i] == Kinematic::free; }
  int find_body(const std::string& name) const {
    for (std::size_t i = 0; i < bodies.size(); ++i)
      if (bodies[i].name == name) return static_cast<int>(i);
    return -1;
  }
};

// Axis-aligned bounding box of x[begin, end), the one definition of a bounding box: NaN
// coordinates are ignored, a zero bound is +0; computed in parallel (simd kernels), the same
// for any thread count and instruction set.
void points_bounds(const Points& x, int begin, int end, Vec3& lo, Vec3& hi);
// The bounding box of a body's current nodes (points_bounds).
void body_bounds(const World& w, int body, Vec3& lo, Vec3& hi);
// Area-weighted outward normal (unnormalised) of a body's surface vertex at body-local index s.
Vec3 vertex_normal(const World& w, int body, int s);
// Enclosed volume of a body's current surface (divergence theorem), m^3.
double enclosed_volume(const World& w, int body);
// Kinetic energy of every node, sum of m v^2 / 2, J, in node order: the state's, outside the
// step (the energy audit books it within the step's own pass over the nodes, energy_audit.hpp).
double kinetic_energy(const World& w);
// Mean rest length of a body's springs, m (0 without springs).
double mean_rest_length(const World& w, int body);
// Mean length of a body's surface edges (faces' edges, each interior edge counted from both of its
// faces: the mean is unchanged) at positions x (w.x or w.x0), m; 0 without faces.
double mean_surface_edge(const World& w, int body, const Points& x);

// ---- The contact's three length scales, one home each, named for what they measure:
// The rest spring length of a body, m: the mean rest length of its springs; for a body without
// springs (a rigid or hand-made one) the spacing of a uniform lattice of its nodes over its
// bounding box, largest extent / cbrt(nodes). The automatic force's length scale without a grid
// (collision.hpp: the separation speed) and the automatic voxel size of a host without a surface.
double rest_spring_length(const World& w, int body);
// The mean surface edge at rest (w.x0; w.x before the rest state is recorded), m: the automatic
// voxel size (initializer.hpp: host_node_spacing) and the grid warnings (run/warnings.cpp).
double rest_surface_edge(const World& w, int body);
// The mean surface edge at the current positions (w.x), m: spatial hashing's automatic cell
// (hash.cpp) and Bullet's collision margin (reference/bullet_engine.cpp).
double current_surface_edge(const World& w, int body);

}  // namespace harness
