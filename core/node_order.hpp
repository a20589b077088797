// Node order by locality, chosen at world build (world_build.cpp): a body's nodes renumbered so
// that nodes joined by a spring lie close together in the node arrays, and its springs sorted by
// their renumbered ends. The step reads every spring's two ends and sums every node's springs
// (spring_forces.hpp): with neighbours near each other in memory, the positions it gathers and the
// spring results it sums are still in cache when they are read again.
//
// The body's surface vertices stay first (nodes [0, n_surface), the convention every surface
// reader relies on): one order over the whole body, split stably into its surface nodes, then its
// interior ones. Outputs keep the scene's numbering (Body::scene_node, world.hpp): the order is
// internal.
#pragma once

#include "core/shapes/shapes.hpp"
#include "core/world.hpp"

#include <string>
#include <vector>

namespace harness {

// The order a world is built in unless told otherwise (SimulationOptions::layout, the command
// line's --node-order): the scene's own. `harness bench` measures the others against it (rows
// step_order_*, step_shuffled_order_*): the generators already emit their nodes lattice by lattice
// and ring by ring (rcm and morton change the step by a few per cent there), while a numbering
// with no locality (a shuffled mesh) costs up to twice the step, and rcm takes it back. The
// layout changes the order of the force sums, hence the last bits of every state, and runs that
// chatter amplify them: the committed results were made in the scene's order.
constexpr NodeOrder kDefaultNodeOrder = NodeOrder::scene;

// "scene", "morton" or "rcm"; false for any other name.
bool parse_node_order(const std::string& name, NodeOrder& out);

// The permutation of a model's nodes: perm[new] = old (the scene's local index of the node placed
// at new), a permutation of [0, n) that keeps [0, n_surface) in place as a set. Deterministic:
// ties are broken by the scene's index.
std::vector<int> node_permutation(const ShapeModel& m, NodeOrder order);

// Renumbers the model by perm (node_permutation's form): nodes, lumped volumes, faces, springs
// (ends renumbered, then sorted by (lower end, higher end), their kappa and role alike).
void apply_node_permutation(ShapeModel& m, const std::vector<int>& perm);

}  // namespace harness
