// The key table (core/scene/keys.hpp) is the one statement of the scene format: the committed
// JSON Schema is the generator's output, the descriptions' defaults and docs/scenes.md's key
// tables agree with it, and the step-counting keys it names are what --dt-divide scales.
#include "core/scene/keys.hpp"
#include "core/scene/scene.hpp"
#include "core/scene/schema.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>

using namespace harness;
using nlohmann::json;

namespace {

std::string source_file(const std::string& rel) {
  std::ifstream in(std::string(HARNESS_SOURCE_DIR) + "/" + rel);
  REQUIRE(in);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// A default as the descriptions and docs/scenes.md write it (keys.hpp).
std::string written(const json& v) { return default_text(v); }

bool same(const json& a, const json& b) {
  if (a.is_number() && b.is_number()) return a.get<double>() == b.get<double>();
  if (a.is_array() && b.is_array()) {
    if (a.size() != b.size()) return false;
    for (std::size_t i = 0; i < a.size(); ++i)
      if (!same(a[i], b[i])) return false;
    return true;
  }
  return a == b;
}

std::vector<const SceneKey*> keys_of(const std::string& kind) {
  std::vector<const SceneKey*> out;
  for (const SceneKey& k : scene_keys())
    if (kind == k.kind) out.push_back(&k);
  return out;
}

}  // namespace

TEST_CASE("experiments/scene.schema.json is the schema the key table generates", "[scene][keys][schema]") {
  const std::string committed = source_file("experiments/scene.schema.json");
  CHECK(json::parse(committed) == json(scene_schema()));
  // Byte for byte: regenerate with `harness schema > experiments/scene.schema.json`.
  CHECK(committed == scene_schema_text());
}

TEST_CASE("every key of the table is a key of a kind the table has, once", "[scene][keys]") {
  std::map<std::string, int> seen;
  for (const SceneKey& k : scene_keys()) {
    INFO(k.kind << "." << k.name);
    CHECK_NOTHROW(scene_kind(k.kind));
    CHECK(++seen[std::string(k.kind) + "." + k.name] == 1);
    if (k.type == KeyType::object || k.type == KeyType::list || k.type == KeyType::force) CHECK_NOTHROW(scene_kind(k.of));
    if (k.type == KeyType::word || k.type == KeyType::words) CHECK_FALSE(k.names.empty());
    if (k.presence == Presence::defaulted && k.type == KeyType::word) {
      bool named = false;
      for (const std::string& n : k.names) named = named || n == k.def.get<std::string>();
      CHECK(named);
    }
    if (k.steps != StepCount::none) CHECK(k.type == KeyType::integer);
  }
}

TEST_CASE("a description's default is made from the table's, never typed", "[scene][keys][schema]") {
  for (const SceneKey& k : scene_keys()) {
    INFO(k.kind << "." << k.name << ": " << k.doc);
    if (k.presence != Presence::defaulted || k.type == KeyType::object) continue;
    CHECK(k.doc.find("Default:") == std::string::npos);  // key_description adds it from the row
    const std::string d = key_description(k);
    const std::string tail = "Default: " + written(k.def) + ".";
    REQUIRE(d.size() >= tail.size());
    CHECK(d.substr(d.size() - tail.size()) == tail);
  }
  // The schema shows the made description.
  const SceneKey& margin = scene_key("contact", "margin");
  CHECK(key_description(margin) == "Voxels added around the region. 0 to 64. Default: 1.");
  CHECK(scene_schema_text().find("\"" + key_description(margin) + "\"") != std::string::npos);
}

TEST_CASE("docs/scenes.md's key tables agree with the table", "[scene][keys][docs]") {
  const std::string doc = source_file("docs/scenes.md");
  // Its sections' key tables (| key | ... |), each for one kind.
  const std::vector<std::pair<std::string, std::string>> sections = {
      {"## Top level", "scene"},          {"### `time`", "time"},           {"## Bodies", "body"},
      {"### `material`", "material"},     {"## Contact pairs", "contact"},  {"## `references`", "references"},
      {"## `output`", "output"}};
  std::map<std::string, std::string> rows;  // kind.key -> the row
  for (const auto& [heading, kind] : sections) {
    const auto start = doc.find("\n" + heading + "\n");
    REQUIRE(start != std::string::npos);
    std::istringstream in(doc.substr(start + heading.size() + 2));
    std::string line;
    bool table = false;
    std::set<std::string> listed;
    while (std::getline(in, line)) {
      if (line.rfind("#", 0) == 0) break;
      if (line.rfind("|", 0) != 0) {
        if (table) break;
        continue;
      }
      table = true;
      if (line.rfind("| key", 0) == 0 || line.rfind("|---", 0) == 0) continue;
      // | `a`, `b` | [type |] default | meaning |
      std::vector<std::string> cells;
      std::string cell;
      for (std::size_t i = 1; i < line.size(); ++i) {
        if (line[i] == '|' && line[i - 1] != '\\') {
          cells.push_back(cell);
          cell.clear();
        } else {
          cell += line[i];
        }
      }
      REQUIRE(cells.size() >= 3);
      const std::string def = std::regex_replace(cells[cells.size() - 2], std::regex("^ +| +$"), "");
      const std::regex name_re("`([a-z_]+)`");
      for (auto it = std::sregex_iterator(cells[0].begin(), cells[0].end(), name_re); it != std::sregex_iterator(); ++it) {
        const std::string name = (*it)[1];
        INFO(heading << ": " << name << ", default " << def);
        listed.insert(name);
        rows[kind + "." + name] = line;
        const SceneKey* k = nullptr;
        for (const SceneKey* c : keys_of(kind))
          if (name == c->name) k = c;
        REQUIRE(k != nullptr);  // the docs list no key the loader does not have
        if (def == "required" || def.rfind("required,", 0) == 0) {
          CHECK(k->presence == Presence::required);
          continue;
        }
        if (def.rfind("required ", 0) == 0) {  // "required with ...": a condition the reader checks
          CHECK(k->presence == Presence::optional);
          continue;
        }
        CHECK(k->presence != Presence::required);
        std::string literal = def;
        if (literal.size() > 2 && literal.front() == '`' && literal.back() == '`') literal = literal.substr(1, literal.size() - 2);
        json v;
        bool parsed = true;
        try {
          v = json::parse(literal);
        } catch (const json::exception&) {
          parsed = false;  // a phrase: "none", "below", "the file's stem", "no solvers"
        }
        if (parsed && k->presence == Presence::defaulted && k->type != KeyType::object) {
          CHECK(same(v, k->def));
        } else {
          CHECK((k->presence != Presence::defaulted || k->type == KeyType::object));
        }
      }
    }
    for (const SceneKey* k : keys_of(kind)) {
      INFO(heading << ": the docs have no row for " << k->name);
      CHECK(listed.count(k->name) == 1);
    }
  }
  // The keys of what a table row describes in a line: settle, drivers, loads, pressure.
  const std::vector<std::pair<std::string, std::string>> inline_kinds = {
      {"time.settle", "settle"}, {"body.drivers", "driver"}, {"body.loads", "load"}, {"body.pressure", "pressure"}};
  for (const auto& [row, kind] : inline_kinds) {
    REQUIRE(rows.count(row) == 1);
    for (const SceneKey* k : keys_of(kind)) {
      INFO(row << " names " << k->name);
      CHECK(rows[row].find("\"" + std::string(k->name) + "\"") != std::string::npos);
      const std::string with_default = "\"" + std::string(k->name) + "\": ";
      const auto at = rows[row].find(with_default);
      if (at != std::string::npos && k->presence == Presence::defaulted) {
        const std::string rest = rows[row].substr(at + with_default.size());
        const std::string value = rest.substr(0, rest.find_first_of(",}"));
        CHECK(same(json::parse(value), k->def));
      }
    }
  }
  // The shape table: each type's keys, and the defaults it gives in parentheses.
  for (const auto& [word, variant] : scene_variants("shape")) {
    const auto at = doc.find("| `" + word + "` |");
    REQUIRE(at != std::string::npos);
    const std::string row = doc.substr(at, doc.find('\n', at) - at);
    for (const SceneKey* k : keys_of(variant->name)) {
      INFO("shape " << word << ": " << k->name);
      const auto pos = row.find("`" + std::string(k->name) + "`");
      CHECK(pos != std::string::npos);
      const std::string after = row.substr(pos + std::string(k->name).size() + 2);
      if (after.rfind(" (", 0) == 0 && k->presence == Presence::defaulted && k->type != KeyType::word) {
        const std::string value = after.substr(2, after.find_first_of(";)") - 2);
        CHECK(same(json::parse(value), k->def));
      }
    }
  }
}

TEST_CASE("running at dt / N scales exactly the keys that count steps, defaults included", "[scene][keys][dt]") {
  const std::string text = R"({
    "time": {"dt": 1e-4, "steps": 30, "settle": {"max_steps": 50}},
    "effects": ["springs", "drivers", "loads", "pressure"],
    "bodies": [{"name": "s", "shape": {"type": "sphere", "radius": 0.01, "subdivisions": 1},
                "drivers": [{"select": {"all": true}, "velocity": [0, 0, 1], "from_step": 3, "to_step": 7},
                            {"select": {"all": true}, "velocity": [0, 0, 1]}],
                "loads": [{"select": {"all": true}, "force": [0, 0, 1], "ramp_steps": 4}],
                "pressure": {"to": 10, "ramp_steps": 5}}],
    "output": {"frames_every": 6}
  })";
  SceneSource src = parse_scene_source(text, "dt.json");
  rescale_steps(src.doc, 4);
  const Scene s = scene_from_source(src);
  CHECK(s.dt == 1e-4 / 4);
  CHECK(s.steps == 120);
  CHECK(s.window == 4000);  // left out: its default, scaled
  CHECK(s.settle.max_steps == 200);
  CHECK(s.bodies[0].drivers[0].from_step == 9);  // step 3 at dt covers steps 9..12 at dt / 4
  CHECK(s.bodies[0].drivers[0].to_step == 28);
  CHECK(s.bodies[0].drivers[1].from_step == 0);
  CHECK(s.bodies[0].drivers[1].to_step == -1);
  CHECK(s.bodies[0].loads[0].ramp_steps == 16);
  CHECK(s.bodies[0].pressure.ramp_steps == 20);
  CHECK(s.references.every == 4);  // references left out: made, its default scaled
  CHECK(s.frames_every == 24);
  // The same as scaling the validated scene (what --dt-divide did before: rescale_dt).
  CHECK(s.resolved == rescale_dt(parse_scene(text, "dt.json"), 4).resolved);
  // --dt: the same at the time step itself.
  SceneSource at = parse_scene_source(text, "dt.json");
  rescale_to_dt(at.doc, 2.5e-5);
  CHECK(scene_from_source(at).steps == 120);
  // Any other time step: every count times dt / S, rounded to the nearest (at least 1); step k at
  // dt covers the steps from (k - 1) dt / S + 1 on.
  SceneSource odd = parse_scene_source(text, "dt.json");
  rescale_to_dt(odd.doc, 3e-5);  // 10/3 steps per step
  const Scene o = scene_from_source(odd);
  CHECK(o.dt == 3e-5);
  CHECK(o.steps == 100);
  CHECK(o.window == 3333);
  CHECK(o.settle.max_steps == 167);
  CHECK(o.bodies[0].drivers[0].from_step == 8);  // (3 - 1) 10/3 + 1 = 7.67
  CHECK(o.bodies[0].drivers[0].to_step == 23);   // 7 x 10/3 = 23.3
  CHECK(o.bodies[0].loads[0].ramp_steps == 13);
  CHECK(o.bodies[0].pressure.ramp_steps == 17);
  CHECK(o.frames_every == 20);
  SceneSource big = parse_scene_source(text, "dt.json");
  rescale_to_dt(big.doc, 2e-4);  // half a step per step: implicit Euler at a large dt
  const Scene b = scene_from_source(big);
  CHECK(b.steps == 15);
  CHECK(b.settle.max_steps == 25);
  CHECK(b.bodies[0].drivers[0].from_step == 2);
  CHECK(b.bodies[0].drivers[0].to_step == 4);  // 3.5, rounded half away from zero
  CHECK(b.frames_every == 3);
  SceneSource tiny = parse_scene_source(text, "dt.json");
  CHECK_THROWS_AS(rescale_to_dt(tiny.doc, 1e-12), InputError);  // a million times off
  SceneSource zero = parse_scene_source(text, "dt.json");
  CHECK_THROWS_AS(rescale_to_dt(zero.doc, 0.0), InputError);
}
