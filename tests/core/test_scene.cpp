// Scene loading: strict validation, one clear message per bad input naming file and key path.
#include "core/collision/responses/force_rule.hpp"
#include "core/run/run_scene.hpp"
#include "core/scene/scene.hpp"
#include "core/simulation.hpp"

#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>

#include <unistd.h>

using namespace harness;
namespace fs = std::filesystem;

namespace {
const char* kGood = R"({
  "name": "good",
  "time": {"dt": 1e-4, "steps": 3},
  "effects": ["springs", "contact"],
  "bodies": [
    {"name": "layer", "shape": {"type": "box", "min": [0,0,0], "max": [0.04,0.04,0.01], "cells": [4,4,1]},
     "pins": [{"side": "-z"}]},
    {"name": "ball", "shape": {"type": "sphere", "center": [0.02,0.02,0.02], "radius": 0.008, "subdivisions": 1}}
  ],
  "contacts": [{"host": "layer", "guest": "ball"}]
})";

// Returns the message of the InputError thrown by loading and building `text`, or "" if none.
std::string error_of(const std::string& text, const std::string& file = "scene.json") {
  try {
    Scene s = parse_scene(text, file);
    Simulation sim(s);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

std::string replace(std::string s, const std::string& from, const std::string& to) {
  const auto p = s.find(from);
  REQUIRE(p != std::string::npos);
  return s.replace(p, from.size(), to);
}

fs::path temp_dir() {
  static int n = 0;
  fs::path d = fs::temp_directory_path() / ("harness_scene_test_" + std::to_string(::getpid()) + "_" + std::to_string(n++));
  fs::create_directories(d);
  return d;
}
}  // namespace

TEST_CASE("a good scene loads, with defaults written into the resolved scene", "[scene]") {
  REQUIRE(error_of(kGood) == "");
  Scene s = parse_scene(kGood, "scene.json");
  CHECK(s.resolved["time"]["integrator"] == "symplectic_euler");
  CHECK(s.resolved["contacts"][0]["detector"] == "voxel");
  CHECK(s.resolved["contacts"][0]["region"] == "half");
  CHECK(s.resolved["contacts"][0]["margin"] == 1);
  CHECK(s.resolved["contacts"][0]["force"] == "auto");
  CHECK(s.resolved["bodies"][1]["material"]["density"] == 1000.0);
  CHECK(s.resolved["gravity"][2] == Approx(-9.81));
  CHECK(s.has(kSprings));
  CHECK_FALSE(s.has(kGravity));
}

TEST_CASE("effects not listed are not built", "[scene][effects]") {
  Simulation sim(parse_scene(replace(kGood, R"("springs", "contact")", R"("springs")"), "scene.json"));
  CHECK(sim.effects_simulated() == std::vector<std::string>{"springs"});
  REQUIRE(sim.pairs().size() == 1);
  CHECK(sim.pairs()[0].collision == nullptr);  // contact not listed: never built, never timed
  sim.step();
  CHECK(sim.last().detect_us == 0.0);
  CHECK(sim.last().eliminate_us == 0.0);
  for (auto k : sim.world().kinematic) CHECK(k == Kinematic::free);  // pins not listed
}

TEST_CASE("bad input: one message naming the file and the key path", "[scene][bad-input]") {
  struct Case {
    const char* what;
    std::string text;
    const char* expect;  // substring of the message
  };
  const std::string g = kGood;
  const std::vector<Case> cases = {
      {"malformed JSON", replace(g, R"("steps": 3},)", R"("steps": 3,,)"), "scene.json:3:"},
      {"unknown key", replace(g, R"("name": "good",)", R"("name": "good", "colour": 1,)"), "scene.json: colour: unknown key"},
      {"unknown nested key", replace(g, R"("radius": 0.008)", R"("radius": 0.008, "radus": 1)"), "bodies.1.shape.radus: unknown key"},
      {"wrong type", replace(g, R"("steps": 3)", R"("steps": "3")"), "time.steps: expected a number"},
      {"missing required key", replace(g, R"("dt": 1e-4, )", ""), "time.dt: missing required key"},
      {"dt <= 0", replace(g, R"("dt": 1e-4)", R"("dt": 0)"), "time.dt: value 0 out of range"},
      {"negative dt", replace(g, R"("dt": 1e-4)", R"("dt": -1)"), "time.dt: value -1 out of range"},
      {"negative steps", replace(g, R"("steps": 3)", R"("steps": -5)"), "time.steps: value -5 out of range"},
      {"NaN literal", replace(g, R"("radius": 0.008)", R"("radius": NaN)"), "scene.json:"},
      {"infinite number", replace(g, R"("radius": 0.008)", R"("radius": 1e999)"), "scene.json:8:88: malformed JSON: number overflow"},
      {"duplicate body names", replace(g, R"("name": "ball")", R"("name": "layer")"), "bodies.1.name: duplicate body name"},
      {"unknown body in contact", replace(g, R"("guest": "ball")", R"("guest": "bal")"), "contacts.0.guest: unknown body"},
      {"empty selection", replace(g, R"({"side": "-z"})", R"({"box": {"min": [1,1,1], "max": [2,2,2]}})"), "bodies.0.pins.0: selection selects no node"},
      {"unknown effect", replace(g, R"("springs", "contact")", R"("springs", "magic")"), "effects.1: unknown effect"},
      {"bad enum", replace(g, R"("host": "layer")", R"("host": "layer", "eliminator": "cone")"), "contacts.0.eliminator: unknown value"},
      {"fractional integer", replace(g, R"("steps": 3)", R"("steps": 2.5)"), "time.steps: expected an integer"},
      {"vector of wrong length", replace(g, R"("center": [0.02,0.02,0.02])", R"("center": [0.02,0.02])"), "bodies.1.shape.center: expected a list of 3 numbers"},
      {"duplicate key", replace(g, R"("name": "good",)", R"("name": "good", "name": "again",)"), "duplicate key \"name\""},
      {"absurd cells", replace(g, R"("cells": [4,4,1])", R"("cells": [4,4,100000])"), "bodies.0.shape.cells.2"},
      {"not an object", "[1,2,3]", "scene.json: (top level): expected an object"},
      {"empty file", "", "scene.json:1:1"},
  };
  for (const Case& c : cases) {
    INFO(c.what);
    const std::string msg = error_of(c.text);
    INFO(msg);
    CHECK(msg.find(c.expect) != std::string::npos);
    CHECK(msg.find('\n') == std::string::npos);
  }
}

TEST_CASE("bad mesh files are bad input naming the scene key and the mesh", "[scene][bad-input][mesh]") {
  const fs::path dir = temp_dir();
  const std::string scene_file = (dir / "scene.json").string();
  auto mesh_scene = [](const std::string& path) {
    return R"({"name":"m","time":{"dt":1e-4,"steps":1},"effects":["springs"],
      "bodies":[{"name":"m","shape":{"type":"mesh","path":")" + path + R"("}}]})";
  };
  auto write = [&](const std::string& name, const std::string& content) {
    std::ofstream(dir / name) << content;
  };
  // A tetrahedron with one face missing (not closed); one with an index out of range;
  // absurd counts; a directory instead of a file.
  write("open.off", "OFF\n4 3 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n");
  write("range.off", "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 9\n");
  write("absurd.off", "OFF\n4000000000 4 0\n0 0 0\n");
  write("garbage.obj", "v 0 0 0\nv 1 0 zero\n");
  fs::create_directories(dir / "adir.off");
  struct Case {
    std::string path;
    const char* expect;
  };
  for (const Case& c : {Case{"missing.off", "bodies.0.shape.path"}, Case{"open.off", "open.off"},
                        Case{"range.off", "range.off"}, Case{"absurd.off", "absurd.off"},
                        Case{"garbage.obj", "garbage.obj:2"}, Case{"adir.off", "adir.off"}}) {
    INFO(c.path);
    const std::string msg = error_of(mesh_scene(c.path), scene_file);
    INFO(msg);
    CHECK(msg.find(c.expect) != std::string::npos);
    CHECK(msg.find("scene.json: bodies.0.shape.path") != std::string::npos);
  }
  // A good closed mesh loads, relative to the scene file.
  write("tet.off", "OFF\n4 4 0\n0 0 0\n0.01 0 0\n0 0.01 0\n0 0 0.01\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n");
  CHECK(error_of(mesh_scene("tet.off"), scene_file) == "");
  fs::remove_all(dir);
}

TEST_CASE("overrides given with --set apply before validation", "[scene][set]") {
  Scene s = parse_scene(kGood, "scene.json", {{"contacts.0.force", "2.5"}, {"time.dt", "5e-5"},
                                              {"references.solvers", R"(["cgal"])"}});
  CHECK(s.contacts[0].spec.force_rule == "constant");
  CHECK(s.contacts[0].spec.force_parameters == std::vector<double>{2.5});
  CHECK(s.dt == 5e-5);
  CHECK(s.references.cgal);
  auto msg = [&](const std::string& k, const std::string& v) {
    try {
      parse_scene(kGood, "scene.json", {{k, v}});
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  CHECK(msg("contacts.5.force", "1").find("--set contacts.5.force: index 5 out of range") != std::string::npos);
  CHECK(msg("time.dt", "{oops").find("--set time.dt: value is not valid JSON") != std::string::npos);
  // A bare word is a string, as --grid takes it; a word the key does not accept is refused by
  // the loader, and what is neither JSON nor a word is refused as JSON.
  CHECK(msg("time.integrator", "implicit_euler").empty());
  CHECK(msg("time.integrator", "sideways").find("scene.json: time.integrator") != std::string::npos);
  CHECK(msg("time.dt", "1e-3x").find("--set time.dt: value is not valid JSON") != std::string::npos);
  CHECK(msg("time.dt", "fast").find("scene.json: time.dt") != std::string::npos);
  CHECK(msg("time.dtt", "1").find("scene.json: time.dtt: unknown key") != std::string::npos);
}
