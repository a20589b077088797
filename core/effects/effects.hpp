// The table of effects and the one factory (effect.hpp has the interface). Adding an effect:
// its flag and its word in core/scene/scene.hpp and readers.cpp (EffectFlag, effect_names(): the
// scene layer names the effects, so that it never includes this layer), a file pair
// core/effects/<name>.{hpp,cpp} with its maker, and one line in effect_table() (effects.cpp). The table's order is the order of
// evaluation within a step (forces accumulate in it, so it is part of the results' bits).
#pragma once

#include "core/collision/detectors/collision_detector.hpp"
#include "core/effects/effect.hpp"

#include <memory>
#include <vector>

namespace harness {

struct Scene;
struct Pair;

// Nodes of one driver, resolved from its selection at rest.
struct DriverNodes {
  std::vector<int> nodes;
  Vec3 velocity = Vec3::Zero();
  int from_step = 0, to_step = -1;
};

// Nodes of one load, resolved from its selection at rest.
struct LoadNodes {
  std::vector<int> nodes;
  Vec3 force = Vec3::Zero();  // N, total over the nodes
  int ramp_steps = 0;
};

// What a maker may read or initialise. Selections are resolved before the effects are made.
struct EffectBuild {
  const Scene& scene;
  World& world;
  std::vector<Pair>& pairs;
  const std::vector<int>& pinned_nodes;
  const std::vector<DriverNodes>& drivers;
  const std::vector<LoadNodes>& loads;
  ExactDetectorMaker exact_detectors = nullptr;
};

using EffectMaker = std::unique_ptr<Effect> (*)(EffectBuild&);

struct EffectEntry {
  unsigned flag;     // EffectFlag
  const char* name;  // as the scene lists it
  EffectMaker make;  // may return null: listed, but nothing to simulate (pressure on no body)
};

const std::vector<EffectEntry>& effect_table();

// The effects the scene lists, in table order.
std::vector<std::unique_ptr<Effect>> make_effects(EffectBuild& b);

}  // namespace harness
