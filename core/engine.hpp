// A peer engine: another library's solver stepping the harness's world in place of the
// harness's own effects and integrator (reference/bullet_engine.hpp: Bullet's soft bodies).
// The harness still builds the world (nodes, springs, masses, pins, drivers), runs the
// kinematic effects' begin_step each step (pins and drivers set World::kinematic and kin_v,
// which the engine follows), and measures, records and compares the engine's states exactly
// as its own (references, steps.csv, summary.json, frames, --compare). Core knows only this
// interface; engines live in reference/.
#pragma once

#include "core/world.hpp"

#include <nlohmann/json.hpp>

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace harness {

struct Scene;

// What one engine step reports per contact pair (in Scene::contacts order) and in all.
struct EngineStep {
  std::vector<int> contacts;  // contacts the engine generated for each pair this step
  double detect_us = 0.0;     // wall time of the engine's collision detection, microseconds
};

class StepEngine {
 public:
  virtual ~StepEngine() = default;
  virtual const char* name() const = 0;
  // Advances the world one step of dt (step: 1-based number of the step). Reads the nodes'
  // kinematic state (pinned, driven with kin_v, free) and writes x and v of every node.
  virtual EngineStep step(World& w, int step, double dt) = 0;
  // The engine's settings and version, for summary.json "engine".
  virtual nlohmann::json describe() const = 0;
  // What the steps.csv "detector" column and summary.json pairs' "detector" say.
  virtual const char* contact_model() const = 0;
};

// Makes the engine for a built world (before the first step). Throws InputError naming the
// scene key of anything the engine cannot represent.
using EngineMaker = std::function<std::unique_ptr<StepEngine>(const Scene& scene, const World& w)>;

}  // namespace harness
