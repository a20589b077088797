// Defaults are written once, in the key table (core/scene/keys.cpp): a ContactSpec is made from it
// (contact_spec_defaults, or the loader), never from the struct, and a spec that was not is
// refused; the structs a scene fills from an empty section hold the table's defaults.
#include "core/collision/collision.hpp"
#include "core/effects/effects.hpp"
#include "core/scene/keys.hpp"
#include "core/scene/scene.hpp"
#include "tests/core/collision/collision_test_worlds.hpp"

#include <catch2/catch.hpp>

#include <stdexcept>
#include <string>

using namespace harness;
using nlohmann::json;

namespace {

const json& def(const char* kind, const char* name) { return scene_key(kind, name).def; }

template <class E>
E word_of(const char* kind, const char* name) {
  const std::string w = def(kind, name).get<std::string>();
  for (const auto& [v, n] : scene_words<E>())
    if (w == n) return v;
  FAIL("no enumerator for " << kind << "." << name << " = " << w);
  return E{};
}

// 0 for "auto" (the Scene's automatic length), else the number.
double length_of(const char* kind, const char* name) {
  const json& v = def(kind, name);
  return v.is_string() ? 0.0 : v.get<double>();
}

void check_contact_defaults(const ContactSpec& s) {
  CHECK(s.made == kContactSpecMade);
  CHECK(std::string(to_string(s.detector)) == def("contact", "detector").get<std::string>());
  CHECK(s.voxel_size == length_of("contact", "voxel_size"));
  CHECK(s.cell_size == length_of("contact", "cell_size"));
  CHECK(s.region == word_of<Region>("contact", "region"));
  CHECK(s.margin == def("contact", "margin").get<int>());
  CHECK(s.host_nodes == word_of<HostNodes>("contact", "host_nodes"));
  CHECK(std::string(to_string(s.eliminator)) == def("contact", "eliminator").get<std::string>());
  CHECK(s.orient == word_of<Orient>("contact", "orient"));
  CHECK(s.two_sided == def("contact", "two_sided").get<bool>());
  CHECK(s.invert_push == def("contact", "invert_push").get<bool>());
  CHECK(s.separation_time == def("contact", "separation_time").get<double>());
  REQUIRE(def("contact", "force") == "auto");
  CHECK(s.force_rule == ForceRule::automatic);
}

const char* kMinimal = R"({
  "time": {"dt": 1e-4, "steps": 10},
  "effects": ["springs", "contact"],
  "bodies": [
    {"name": "a", "shape": {"type": "box", "min": [0, 0, 0], "max": [0.01, 0.01, 0.01], "cells": [1, 1, 1]},
     "material": {}},
    {"name": "b", "shape": {"type": "cylinder", "center": [0, 0, 0.02], "radius": 0.005, "length": 0.01},
     "material": {}}
  ],
  "contacts": [{"host": "a", "guest": "b"}]
})";

}  // namespace

TEST_CASE("contact_spec_defaults holds the key table's defaults", "[scene][defaults]") {
  const ContactSpec s = contact_spec_defaults();
  check_contact_defaults(s);
  CHECK(s.host == -1);
  CHECK(s.guest == -1);
}

TEST_CASE("a contact that gives no parameter gets the table's defaults", "[scene][defaults]") {
  const Scene sc = parse_scene(kMinimal, "minimal.json");
  REQUIRE(sc.contacts.size() == 1);
  const ContactSpec& s = sc.contacts[0].spec;
  check_contact_defaults(s);
  CHECK(s.host == 0);
  CHECK(s.guest == 1);
}

TEST_CASE("the sections of a scene that give nothing hold the table's defaults", "[scene][defaults]") {
  const Scene sc = parse_scene(kMinimal, "minimal.json");
  CHECK(sc.window == def("time", "window").get<int>());
  CHECK(std::string(scene_word(sc.integrator)) == def("time", "integrator").get<std::string>());
  CHECK(std::string(scene_word(sc.guard)) == def("time", "guard").get<std::string>());
  CHECK(std::string(scene_word(sc.frame_format)) == def("output", "format").get<std::string>());
  CHECK(sc.frames_every == def("output", "frames_every").get<int>());
  CHECK(sc.trajectory == def("output", "trajectory").get<bool>());
  const json g = def("scene", "gravity");
  CHECK(sc.gravity == Vec3(g[0].get<double>(), g[1].get<double>(), g[2].get<double>()));
  CHECK(sc.references.every == def("references", "every").get<int>());
  CHECK(sc.references.volume == def("references", "volume").get<bool>());
  for (const BodySpec& b : sc.bodies) {
    INFO(b.name);
    CHECK(b.material.density == def("material", "density").get<double>());
    CHECK(b.material.stiffness == def("material", "stiffness").get<double>());
    CHECK(std::string(scene_word(b.material.law)) == def("material", "law").get<std::string>());
    CHECK(b.material.nonlinearity == def("material", "nonlinearity").get<double>());
    CHECK(b.material.damping == def("material", "damping").get<double>());
    CHECK(b.material.mass_damping == def("material", "mass_damping").get<double>());
  }
  CHECK(sc.bodies[1].shape.segments == def("shape.cylinder", "segments").get<int>());
  CHECK(sc.bodies[1].shape.rings == def("shape.cylinder", "rings").get<int>());
}

TEST_CASE("a ContactSpec not made from the key table is refused", "[scene][defaults][collision]") {
  World w;
  const int host = test::add_body(w, "host", test::icosahedron(Vec3(0, 0, 0), 1.0, true));
  const int guest = test::add_body(w, "guest", test::cloud({Vec3(0.5, 0.5, 0.5)}));
  ContactSpec bare{};  // the struct alone: no table behind it
  bare.host = host;
  bare.guest = guest;
  CHECK_THROWS_AS(Collision(w, bare), std::logic_error);
  ContactSpec made = contact_spec_defaults();
  made.host = host;
  made.guest = guest;
  CHECK_NOTHROW(Collision(w, made));
}

TEST_CASE("each enumerated word set is one table: the shapes' variants are its words", "[scene][keys]") {
  std::vector<std::string> variants;
  for (const auto& [word, kind] : scene_variants("shape")) variants.push_back(word);
  CHECK(variants == word_list<ShapeType>());
  CHECK(scene_key("shape", "type").names == word_list<ShapeType>());
  CHECK(scene_key("references", "solvers").names == word_list<Solver>());
  CHECK(scene_key("selection", "side").names == word_list<Side>());
  CHECK(scene_key("shape.sphere", "fill").names == word_list<FillWord>());
  CHECK(word_value<Solver>("fcl") == Solver::fcl);
  CHECK_THROWS_AS(word_value<Solver>("bullet"), std::logic_error);
  // A side's word gives its axis and sign.
  const Scene sc = parse_scene(R"({"time": {"dt": 1e-4, "steps": 1}, "effects": ["springs", "pins"],
    "bodies": [{"name": "a", "shape": {"type": "box", "min": [0, 0, 0], "max": [1, 1, 1], "cells": [1, 1, 1]},
                "pins": [{"side": "-x"}, {"side": "+z"}]}]})", "sides.json");
  REQUIRE(sc.bodies[0].pins.size() == 2);
  CHECK((sc.bodies[0].pins[0].axis == 0 && sc.bodies[0].pins[0].sign == -1));
  CHECK((sc.bodies[0].pins[1].axis == 2 && sc.bodies[0].pins[1].sign == 1));
  CHECK(sc.bodies[0].shape.type == ShapeType::box);
}

TEST_CASE("the effects are named by the scene layer, in the order a step makes them", "[scene][keys][effects]") {
  const auto names = effect_names();
  const auto& table = effect_table();
  REQUIRE(table.size() == names.size());
  for (std::size_t i = 0; i < names.size(); ++i) {
    CHECK(table[i].flag == static_cast<unsigned>(names[i].first));
    CHECK(std::string(table[i].name) == names[i].second);
  }
  std::vector<std::string> words;
  for (const auto& [flag, name] : names) words.emplace_back(name);
  CHECK(scene_key("scene", "effects").names == words);
}
