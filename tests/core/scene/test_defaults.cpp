// Defaults are written once, in the key table (core/scene/keys.cpp): a ContactSpec is made from it
// (contact_spec_defaults, or the loader), never from the struct, and a spec that was not is
// refused; the structs a scene fills from an empty section hold the table's defaults.
#include "core/collision/responses/force_rule.hpp"
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
  CHECK(s.detector == def("contact", "detector").get<std::string>());
  CHECK(s.voxel_size == length_of("contact", "voxel_size"));
  CHECK(s.cell_size == length_of("contact", "cell_size"));
  CHECK(s.region == word_of<Region>("contact", "region"));
  CHECK(s.margin == def("contact", "margin").get<int>());
  CHECK(s.host_nodes == word_of<HostNodes>("contact", "host_nodes"));
  CHECK(s.eliminator == def("contact", "eliminator").get<std::string>());
  CHECK(s.orient == word_of<Orient>("contact", "orient"));
  CHECK(s.two_sided == def("contact", "two_sided").get<bool>());
  CHECK(s.invert_push == def("contact", "invert_push").get<bool>());
  CHECK(s.separation_time == def("contact", "separation_time").get<double>());
  CHECK(s.damping == def("contact", "damping").get<double>());
  REQUIRE(def("contact", "force") == "auto");
  CHECK(s.force_rule == "auto");
  CHECK(s.force_parameters.empty());
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

namespace {

void check_material_defaults(const Material& m) {
  CHECK(m.density == def("material", "density").get<double>());
  CHECK(m.stiffness == def("material", "stiffness").get<double>());
  CHECK(m.youngs_modulus == 0.0);  // optional: absent
  CHECK(m.thickness == 0.0);
  CHECK(std::string(scene_word(m.law)) == def("material", "law").get<std::string>());
  CHECK(m.nonlinearity == def("material", "nonlinearity").get<double>());
  CHECK(m.damping == def("material", "damping").get<double>());
  CHECK(m.mass_damping == def("material", "mass_damping").get<double>());
}

Vec3 vec_of(const char* kind, const char* name) {
  const json& v = def(kind, name);
  return Vec3(v[0].get<double>(), v[1].get<double>(), v[2].get<double>());
}

}  // namespace

TEST_CASE("material_defaults and reference_spec_defaults hold the key table's defaults", "[scene][defaults]") {
  check_material_defaults(material_defaults());
  const ReferenceSpec r = reference_spec_defaults();
  CHECK(r.every == def("references", "every").get<int>());
  CHECK(r.volume == def("references", "volume").get<bool>());
  CHECK(def("references", "solvers").empty());
  CHECK_FALSE((r.cgal || r.fcl || r.ccd));
  // The structs alone hold none of them: a default written in a struct would show here.
  const Material bare{};
  CHECK(bare.density == 0.0);
  CHECK(bare.stiffness == 0.0);
  CHECK(ReferenceSpec{}.every == 0);
}

TEST_CASE("every struct a section fills holds the table's default for each key it leaves out", "[scene][defaults]") {
  const Scene sc = parse_scene(R"({
    "time": {"dt": 1e-4, "steps": 10, "settle": {"max_steps": 5}},
    "effects": ["springs", "drivers", "loads", "pressure"],
    "bodies": [
      {"name": "s", "shape": {"type": "sphere", "radius": 0.01},
       "drivers": [{"select": {"all": true}, "velocity": [0, 0, 1]}],
       "loads": [{"select": {"side": "+z"}, "force": [0, 0, 1]}],
       "pressure": {"to": 100}},
      {"name": "c", "shape": {"type": "cylinder", "center": [0, 0, 0.05], "radius": 0.005, "length": 0.01}},
      {"name": "e", "shape": {"type": "ellipsoid", "center": [0, 0, 0.1], "radii": [0.01, 0.02, 0.01]}}
    ]})", "sections.json");
  CHECK(sc.settle.tolerance == def("settle", "tolerance").get<double>());
  const BodySpec& s = sc.bodies[0];
  check_material_defaults(s.material);
  CHECK(s.velocity == vec_of("body", "velocity"));
  CHECK(s.shape.center == vec_of("shape.sphere", "center"));
  CHECK(s.shape.subdivisions == def("shape.sphere", "subdivisions").get<int>());
  CHECK(s.shape.volume_fill == (def("shape.sphere", "fill") == "volume"));
  REQUIRE(s.drivers.size() == 1);
  CHECK(s.drivers[0].from_step == def("driver", "from_step").get<int>());
  CHECK(s.drivers[0].to_step == def("driver", "to_step").get<int>());
  REQUIRE(s.loads.size() == 1);
  CHECK(s.loads[0].ramp_steps == def("load", "ramp_steps").get<int>());
  CHECK(s.pressure.from == def("pressure", "from").get<double>());
  CHECK(s.pressure.ramp_steps == def("pressure", "ramp_steps").get<int>());
  const ShapeSpec& c = sc.bodies[1].shape;
  CHECK(c.axis == vec_of("shape.cylinder", "axis"));
  CHECK(c.volume_fill == (def("shape.cylinder", "fill") == "volume"));
  CHECK(sc.bodies[2].shape.subdivisions == def("shape.ellipsoid", "subdivisions").get<int>());
}

TEST_CASE("a description's range and Required are made from the row, never typed", "[scene][keys][schema]") {
  for (const SceneKey& k : scene_keys()) {
    INFO(k.kind << "." << k.name << ": " << k.doc);
    const std::string r = range_text(k);
    if (!r.empty()) {  // compared without the case of the first letter (a sentence starts with it)
      const std::string tail = r.substr(1);
      CHECK(k.doc.find(tail) == std::string::npos);
      CHECK(key_description(k).find(tail) != std::string::npos);
    }
    CHECK(k.doc.find("Required") == std::string::npos);
    if (k.presence == Presence::required && k.type != KeyType::always_true)
      CHECK(key_description(k).find("Required") != std::string::npos);
  }
  CHECK(key_description(scene_key("time", "dt")) == "Time step, s. Required; > 0, <= 1000.");
  CHECK(key_description(scene_key("time", "window")).find("1 to 2e9. Default: 1000.") != std::string::npos);
  CHECK(range_text(scene_key("shape.box", "cells")) == "1 to 1000 each");
  CHECK(range_text(scene_key("contact", "voxel_size")) == "> 0, <= 1e6, or \"auto\"");
  CHECK(range_text(scene_key("pressure", "to")) == "-1e9 to 1e9");
  CHECK(range_text(scene_key("material", "damping")) == ">= 0");
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
