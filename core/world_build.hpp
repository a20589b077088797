// Building a scene's world, the first of the simulation's named steps (simulation.hpp): every
// body generated from its shape (shapes/, meshes through mesh.hpp) and laid out in one set of
// node arrays (World, world.hpp): nodes, masses (density x lumped volume), springs with their
// stiffness (material.stiffness, or from youngs_modulus through elastic_map.hpp), surface and
// vertex-face table, rest bounding box; then the kinematic selections (pins, drivers, loads)
// resolved on the rest positions, whether or not their effect is listed.
#pragma once

#include "core/effects/effects.hpp"
#include "core/node_order.hpp"
#include "core/scene/scene.hpp"
#include "core/world.hpp"

#include <vector>

namespace harness {

// How the nodes are laid out (node_order.hpp): the order by locality, and for benches and tests an
// arbitrary numbering to start from (shuffle_seed != 0: each body's surface and interior nodes
// shuffled, as an arbitrary mesh file may number them, before the order is applied).
struct WorldBuild {
  NodeOrder order = kDefaultNodeOrder;
  unsigned long long shuffle_seed = 0;
};

// The world of a scene at rest. Throws InputError (file and key path) for what only shows when
// the bodies are built: a mesh file, a shape the generators refuse, a node without mass.
World build_world(const Scene& scene, const WorldBuild& build = {});

// Global node indices of a body that a selection picks (on the rest positions).
std::vector<int> select_nodes(const World& w, int body, const Selection& sel);

// The nodes every pin, driver and load of the scene selects. Throws InputError naming the
// selection's key path when it selects no node.
struct Kinematics {
  std::vector<int> pinned;
  std::vector<DriverNodes> drivers;
  std::vector<LoadNodes> loads;
};
Kinematics resolve_kinematics(const Scene& scene, const World& world);

}  // namespace harness
