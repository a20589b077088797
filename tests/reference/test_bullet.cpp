// The Bullet engine (reference/bullet_engine.hpp) against physics and against the harness:
//  - the link mapping: a layer pinned below and settled under gravity sags as much with Bullet's
//    links as with the harness's springs (static equilibrium: independent of either integrator);
//  - Bullet's vertex-face contact conserves momentum (two free spheres collide, no gravity, no
//    damping, no pins) and separates them;
//  - what Bullet cannot represent is refused naming the scene key.
#include "core/run/run_scene.hpp"
#include "core/scene/scene.hpp"
#include "core/simulation.hpp"
#include "reference/reference.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <string>

using namespace harness;

namespace {

const char* kLayer = R"({
  "name": "bullet_layer",
  "time": {"dt": 5e-5, "steps": 2000, "integrator": "symplectic_euler",
           "settle": {"tolerance": 1e-4, "max_steps": 40000}},
  "effects": ["springs", "damping", "gravity", "pins"],
  "gravity": [0, 0, -9.81],
  "bodies": [{"name": "layer",
              "shape": {"type": "box", "min": [-0.02, -0.02, 0], "max": [0.02, 0.02, 0.01], "cells": [4, 4, 2]},
              "material": {"density": 1000, "youngs_modulus": 30000, "law": "linear", "mass_damping": 40},
              "pins": [{"side": "-x"}, {"side": "+x"}]}]
})";

const char* kSpheres = R"({
  "name": "bullet_spheres",
  "time": {"dt": 5e-5, "steps": 3000, "integrator": "symplectic_euler"},
  "effects": ["springs", "contact"],
  "bodies": [
    {"name": "a", "shape": {"type": "sphere", "center": [-0.0105, 0, 0], "radius": 0.01, "subdivisions": 2, "fill": "volume"},
     "material": {"density": 1000, "youngs_modulus": 3000, "law": "linear"}, "velocity": [0.2, 0, 0]},
    {"name": "b", "shape": {"type": "sphere", "center": [0.0105, 0.002, 0], "radius": 0.01, "subdivisions": 2, "fill": "volume"},
     "material": {"density": 1500, "youngs_modulus": 3000, "law": "linear"}, "velocity": [-0.1, 0, 0]}],
  "contacts": [{"host": "a", "guest": "b", "detector": "voxel", "voxel_size": 0.002}]
})";

Scene scene_of(const std::string& text, const std::vector<std::pair<std::string, std::string>>& sets = {}) {
  return parse_scene(text, "test.json", sets);
}

// Settles like run_steps: until the residual stays under the tolerance for kSettleWindow steps.
void settle(Simulation& sim) {
  const Scene& sc = sim.scene();
  int below = 0;
  for (int s = 1; s <= sc.steps + sc.settle.max_steps; ++s) {
    sim.step();
    below = sim.residual() <= sc.settle.tolerance ? below + 1 : 0;
    if (s >= sc.steps && below >= kSettleWindow) return;
  }
  FAIL("did not settle: residual " << sim.residual());
}

// Mean downward displacement of the nodes on the layer's top face.
double top_sag(const World& w) {
  double sum = 0.0;
  int n = 0;
  for (int i = 0; i < w.num_nodes(); ++i)
    if (w.x0[i].z() > 0.01 - 1e-9) sum += w.x0[i].z() - w.x[i].z(), ++n;
  return sum / n;
}

Vec3 momentum(const World& w) {
  Vec3 p = Vec3::Zero();
  for (int i = 0; i < w.num_nodes(); ++i) p += w.m[i] * w.v[i];
  return p;
}

SimulationOptions bullet_options(BulletOptions bo = {}) {
  SimulationOptions so;
  so.engine = make_bullet_engine(bo);
  return so;
}

std::string refusal(const std::string& text, const std::vector<std::pair<std::string, std::string>>& sets) {
  try {
    Simulation sim(scene_of(text, sets), bullet_options());
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("Bullet's links sag a pinned layer as much as the harness's springs", "[bullet]") {
  const Scene sc = scene_of(kLayer);
  Simulation own(sc);
  settle(own);
  Simulation bullet(sc, bullet_options());
  settle(bullet);
  const double a = top_sag(own.world()), b = top_sag(bullet.world());
  INFO("sag harness " << a * 1e3 << " mm, Bullet " << b * 1e3 << " mm");
  REQUIRE(a > 1e-4);  // the load does something (0.1 mm at least)
  // Measured 2026-11-23: relative difference 0.05 % (0.2008 / 0.2007 mm); margin 20x -> 1 %. A link stiffness off by a
  // factor 2 (kLST without the 1/m_a + 1/m_b or the iterations) moves it by 30-100 %. At larger
  // strain the two differ by Bullet's link law (bullet_engine.hpp): 1.6 % at E = 3000 Pa here,
  // 14 % at 300 Pa.
  CHECK(std::abs(b - a) / a < 0.01);
  // More position iterations with the stiffness divided among them: the same material.
  BulletOptions bo;
  bo.iterations = 4;
  Simulation bullet4(sc, bullet_options(bo));
  settle(bullet4);
  CHECK(std::abs(top_sag(bullet4.world()) - a) / a < 0.01);
}

// Bullet's links move both ends by inverse mass and its velocity update is (x - x_prev) / dt:
// momentum is conserved exactly until the bodies touch. Its vertex-face contact is not: each body's
// solveConstraints ends with that body's velocity update, and the contacts of the body solved
// after it then move its face nodes without changing their velocity (btDefaultSoftBodySolver
// solves the bodies one after the other). The drift is reported, not bounded: it is Bullet's
// (measured 2026-11-23 in this collision: at most 75 % of sphere a's momentum with the lumped
// masses, 45 % with every node given one mass; docs/findings.md).
TEST_CASE("Bullet's links conserve momentum; its contact separates two free spheres", "[bullet]") {
  Simulation sim(scene_of(kSpheres), bullet_options());
  const World& w = sim.world();
  const Vec3 p0 = momentum(w);
  double scale = 0.0;  // |m v| of sphere a, kg m/s
  for (int i = w.bodies[0].begin; i < w.bodies[0].end; ++i) scale += w.m[i] * 0.2;
  int contacts = 0, free_steps = 0;
  double drift_free = 0.0, drift = 0.0;
  for (int s = 0; s < sim.scene().steps; ++s) {
    sim.step();
    contacts += sim.pairs()[0].last.contacts;
    const double d = (momentum(w) - p0).norm() / scale;
    if (contacts == 0) drift_free = std::max(drift_free, d), ++free_steps;
    drift = std::max(drift, d);
  }
  WARN("Bullet VF_SS: " << contacts << " contacts over the run, momentum drift " << drift << " of sphere a's");
  CHECK(free_steps > 20);  // the spheres start 1 mm apart
  CHECK(drift_free < 1e-12);
  CHECK(contacts > 0);
  // Separated: the centres' relative velocity along x reversed.
  Vec3 va = Vec3::Zero(), vb = Vec3::Zero();
  double ma = 0.0, mb = 0.0;
  for (int i = w.bodies[0].begin; i < w.bodies[0].end; ++i) va += w.m[i] * w.v[i], ma += w.m[i];
  for (int i = w.bodies[1].begin; i < w.bodies[1].end; ++i) vb += w.m[i] * w.v[i], mb += w.m[i];
  CHECK((vb / mb - va / ma).x() > 0.0);
  CHECK(std::string(sim.engine()->contact_model()) == "bullet_vf_ss");
}

TEST_CASE("what Bullet cannot represent is refused naming the key", "[bullet]") {
  CHECK_THAT(refusal(kLayer, {{"bodies.0.material.law", "\"exponential\""}, {"bodies.0.material.nonlinearity", "3"}}),
             Catch::Contains("bodies.0.material.law"));
  CHECK_THAT(refusal(kLayer, {{"bodies.0.material.damping", "0.001"}}), Catch::Contains("bodies.0.material.damping"));
  CHECK_THAT(refusal(kLayer, {{"time.dt", "0.01"}, {"time.guard", "\"substep\""}}), Catch::Contains("time.dt"));
  CHECK_THAT(refusal(kLayer, {{"effects", "[\"springs\", \"loads\"]"},
                              {"bodies.0.loads", "[{\"select\": {\"side\": \"+z\"}, \"force\": [0, 0, -1]}]"}}),
             Catch::Contains("bodies.0.loads"));
  CHECK(refusal(kLayer, {}).empty());
}
