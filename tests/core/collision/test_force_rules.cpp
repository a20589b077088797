// The force rules' registry (core/collision/responses/force_rule.hpp, one file per rule under
// core/collision/rules/): every rule reaches the key table, the loader and docs/scenes.md; a
// rule's stiffness is its force's derivative (finite differences); the guard reads it; the
// Hertz-like rule at exponent 1 is the linear penalty to the bit.
#include "core/collision/responses/collision_eliminator.hpp"
#include "core/collision/responses/force_rule.hpp"
#include "core/effects/effect.hpp"
#include "core/scene/keys.hpp"
#include "core/scene/scene.hpp"
#include "core/simulation.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

using namespace harness;

namespace {

// A pinned block under a small one that starts 2 mm into it, off the host's lattice (aligned, a
// guest node's three nearest host nodes span a plane through it): in contact from step 1.
std::string scene(const std::string& force, double dt = 1e-4) {
  return R"({"name":"r","time":{"dt":)" + std::to_string(dt) + R"(,"steps":0,"guard":"substep"},
    "effects":["springs","pins","gravity","contact"],
    "bodies":[{"name":"a","shape":{"type":"box","min":[0,0,0],"max":[0.04,0.04,0.02],"cells":[4,4,2]},
               "material":{"density":1000,"stiffness":100},"pins":[{"side":"-z"}]},
              {"name":"b","shape":{"type":"box","min":[0.013,0.012,0.018],"max":[0.033,0.032,0.03],"cells":[2,2,2]},
               "material":{"density":1000,"stiffness":100}}],
    "contacts":[{"host":"a","guest":"b","detector":"voxel","voxel_size":0.01,"eliminator":"plane","force":)" +
         force + "}]}";
}

std::string load_error(const std::string& text) {
  try {
    parse_scene(text, "r.json");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// The rule's force on one push of depth d along +z (the eliminator's normal).
double force_at(const ForceRuleDef& r, const std::vector<double>& p, double d) {
  World w;
  ContactSpec spec = contact_spec_defaults();
  std::vector<Push> pushes(1);
  pushes[0].guest = 0, pushes[0].count = 1, pushes[0].hosts[0] = 1, pushes[0].weight[0] = 1.0;
  pushes[0].normal = Vec3(0, 0, 1), pushes[0].depth = d;
  std::vector<int> share;
  std::vector<double> out;
  RuleStep s{w, pushes, 1e-4, 0.01, spec, share};
  r.force(s, p, out);
  return out.at(0);
}

}  // namespace

TEST_CASE("force rules: each reaches the key table, and the loader reads what a scene writes", "[force_rules][scene]") {
  for (const ForceRuleDef& r : force_rules()) {
    INFO(r.name);
    if (r.form == RuleForm::object)
      for (const RuleParameter& p : r.parameters) {
        const SceneKey& k = scene_key(std::string("force.") + r.name, p.name);
        CHECK(k.lo == p.lo);
        CHECK(k.hi == p.hi);
      }
  }
  const SceneKey& force = scene_key("contact", "force");
  CHECK(force.lo == rule_of_form(RuleForm::number)->parameters[0].lo);
  CHECK(force.hi == rule_of_form(RuleForm::number)->parameters[0].hi);

  const Scene a = parse_scene(scene(R"({"rule":"hertz","stiffness":5})"), "r.json");
  CHECK(a.contacts[0].spec.force_rule == "hertz");
  CHECK(a.contacts[0].spec.force_parameters == std::vector<double>{5.0, 1.5});  // exponent: its default
  CHECK(a.resolved["contacts"][0]["force"] == nlohmann::json::parse(R"({"rule":"hertz","stiffness":5,"exponent":1.5})"));
  // {"stiffness": k} is the penalty, resolved as written.
  const Scene b = parse_scene(scene(R"({"stiffness":7})"), "r.json");
  CHECK(b.contacts[0].spec.force_rule == "penalty");
  CHECK(b.resolved["contacts"][0]["force"] == nlohmann::json::parse(R"({"stiffness":7})"));
  CHECK(parse_scene(scene("0.25"), "r.json").contacts[0].spec.force_parameters == std::vector<double>{0.25});

  // Bad input names the key path.
  CHECK(load_error(scene(R"({"rule":"nope","stiffness":5})")).find("r.json: contacts.0.force.rule: unknown rule") == 0);
  CHECK(load_error(scene(R"({"stiffness":5,"exponent":2})")).find("r.json: contacts.0.force.exponent") == 0);
  CHECK(load_error(scene(R"({"rule":"hertz","stiffness":5,"exponent":9})")).find("r.json: contacts.0.force.exponent") == 0);
  CHECK(load_error(scene(R"({"rule":"hertz"})")).find("r.json: contacts.0.force.stiffness") == 0);
  CHECK(load_error(scene(R"("fast")")).find("r.json: contacts.0.force: expected") == 0);
  CHECK(load_error(scene("-1")).find("r.json: contacts.0.force: value -1 out of range") == 0);
}

TEST_CASE("force rules: a rule's stiffness is its force's derivative along the push", "[force_rules][physics]") {
  int checked = 0;
  for (const ForceRuleDef& r : force_rules()) {
    if (!r.stiffness) continue;
    std::vector<double> p;
    for (const RuleParameter& q : r.parameters) p.push_back(std::isnan(q.fallback) ? 500.0 : q.fallback);
    for (double d : {1e-4, 1e-3, 5e-3}) {
      const double e = 1e-3 * d;
      const double fd = (force_at(r, p, d + e) - force_at(r, p, d - e)) / (2.0 * e);
      const double k = r.stiffness(p, d, force_at(r, p, d));
      INFO(r.name << " at depth " << d << ": stiffness " << k << ", finite difference " << fd);
      CHECK(std::abs(k - fd) <= 1e-6 * std::abs(fd));
      // The check can fail: the secant F/d, a plausible wrong stiffness for a power law, misses by
      // a third at exponent 1.5.
      if (std::string(r.name) == "hertz") CHECK(std::abs(force_at(r, p, d) / d - fd) > 0.3 * fd);
      ++checked;
    }
  }
  CHECK(checked >= 6);  // penalty and hertz
}

TEST_CASE("force rules: hertz at exponent 1 is the linear penalty to the bit", "[force_rules]") {
  Simulation lin(parse_scene(scene(R"({"stiffness":400})"), "r.json"));
  Simulation pow1(parse_scene(scene(R"({"rule":"hertz","stiffness":400,"exponent":1})"), "r.json"));
  double largest = 0.0;
  for (int s = 0; s < 300; ++s) {
    lin.step(), pow1.step();
    largest = std::max(largest, lin.pairs()[0].collision->magnitudes().empty() ? 0.0 : lin.pairs()[0].collision->magnitudes()[0]);
  }
  CHECK(largest > 0.0);  // the pair pressed
  CHECK(lin.world().x == pow1.world().x);
  CHECK(lin.world().v == pow1.world().v);
  CHECK(lin.critical_dt() == pow1.critical_dt());
}

TEST_CASE("force rules: the implicit step assembles the rule's stiffness", "[force_rules][implicit]") {
  // Implicit Euler puts each push's block k n n^T in its system: hertz at exponent 1 must give the
  // penalty's state to the bit, and at exponent 1.5 (stiffness k 1.5 d^0.5, another matrix) not.
  auto run = [](const std::string& force) {
    std::string text = scene(force, 5e-4);
    text.replace(text.find(R"("guard":"substep")"), 17, R"("guard":"substep","integrator":"implicit_euler")");
    Simulation sim(parse_scene(text, "r.json"));
    for (int s = 0; s < 40; ++s) sim.step();
    return sim.world().x;
  };
  const Points lin = run(R"({"stiffness":400})");
  CHECK(run(R"({"rule":"hertz","stiffness":400,"exponent":1})") == lin);
  CHECK_FALSE(run(R"({"rule":"hertz","stiffness":8000,"exponent":1.5})") == lin);

  // The blocks the contact effect hands the implicit step: one per pushing contact, k = the
  // rule's dF/d depth at that push's depth (8000 x 1.5 x depth^0.5), along the push's direction.
  Simulation sim(parse_scene(scene(R"({"rule":"hertz","stiffness":8000,"exponent":1.5})"), "r.json"));
  sim.step();
  const Collision& col = *sim.pairs()[0].collision;
  LinearSystem sys;
  for (const auto& e : sim.effects())
    if (std::string(e->name()) == "contact") e->add_jacobian(sim.world(), sys);
  int pushing = 0;
  for (std::size_t i = 0; i < col.pushes().size(); ++i) pushing += col.pushes()[i].count > 0 && col.magnitudes()[i] > 0.0;
  REQUIRE(pushing > 0);
  REQUIRE(static_cast<int>(sys.contacts.size()) == pushing);
  std::size_t b = 0;
  for (std::size_t i = 0; i < col.pushes().size(); ++i) {
    const Push& q = col.pushes()[i];
    if (q.count == 0 || !(col.magnitudes()[i] > 0.0)) continue;
    CHECK(sys.contacts[b].k == Approx(8000.0 * 1.5 * std::sqrt(q.depth)).epsilon(1e-12));
    CHECK(sys.contacts[b].n == q.n);
    ++b;
  }
}

TEST_CASE("force rules: the stability guard reads the rule's stiffness", "[force_rules][guard]") {
  Simulation soft(parse_scene(scene(R"({"rule":"hertz","stiffness":1e3})"), "r.json"));
  Simulation stiff(parse_scene(scene(R"({"rule":"hertz","stiffness":1e8})"), "r.json"));
  Simulation none(parse_scene(scene("0.001"), "r.json"));  // a constant force reports no stiffness
  // Before the first step the guard assumes the rule's stiffness at a depth of one voxel
  // (1e8 x 1.5 x 0.01^0.5 = 1.5e7 N/m per contact against springs of 100 N/m).
  INFO("dt_crit before the first step: hertz k 1e3 " << soft.critical_dt() << " s, k 1e8 " << stiff.critical_dt()
                                                     << " s, constant " << none.critical_dt() << " s");
  CHECK(stiff.critical_dt() < 0.01 * soft.critical_dt());
  CHECK(soft.critical_dt() < none.critical_dt());
  // After a step, the pushes' own depths (the exponent-1 case is the penalty's, above).
  soft.step(), stiff.step(), none.step();
  CHECK(stiff.critical_dt() <= soft.critical_dt());
}

TEST_CASE("docs/scenes.md lists the force rules the registry has", "[force_rules][docs]") {
  std::ifstream in(std::string(HARNESS_SOURCE_DIR) + "/docs/scenes.md");
  REQUIRE(in);
  std::ostringstream ss;
  ss << in.rdbuf();
  // Regenerate the tables with `build/bin/harness rules`.
  CHECK(ss.str().find(force_rules_markdown()) != std::string::npos);
  CHECK(ss.str().find(eliminators_markdown()) != std::string::npos);
  CHECK(ss.str().find(detectors_markdown()) != std::string::npos);
}

TEST_CASE("eliminators: the registry is the scene key's words, the paper's line first", "[force_rules][scene]") {
  const SceneKey& k = scene_key("contact", "eliminator");
  std::vector<std::string> names;
  for (const EliminatorDef& e : eliminators()) names.emplace_back(e.name);
  CHECK(k.names == names);
  CHECK(names.front() == "line");
  CHECK(k.def == "line");
  for (const EliminatorDef& e : eliminators()) {
    INFO(e.name);
    CHECK(std::string(e.doc).size() > 10);
    CHECK(std::string(make_eliminator(e.name)->name()) == e.name);  // the maker makes that one
  }
  CHECK(find_eliminator("projection")->projects);
  CHECK(find_eliminator("volume")->projects);
  CHECK_FALSE(find_eliminator("plane")->projects);
  CHECK(std::string(find_eliminator("distance_field")->detector) == "distance_field");
  CHECK(load_error(scene("0.001").replace(scene("0.001").find("\"plane\""), 7, "\"plane2\"")).find("r.json: contacts.0.eliminator") == 0);
}
