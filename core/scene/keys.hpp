// The scene format's keys, declared once (keys.cpp): one row per key with its type, whether it is
// required or its default, its range, unit and names, whether it counts steps, and its
// description. From this table
//   - the loader (readers.cpp, through check.hpp's accessors) validates each key and writes its
//     default into the resolved scene;
//   - `harness schema` prints the JSON Schema (schema.cpp; experiments/scene.schema.json is its
//     output, checked equal by tests);
//   - --steps, --dt-divide, --dt and the reference levels find the keys that count steps
//     (document.cpp: rescale_steps);
//   - summary.json writes the names of the enumerations (scene_word);
//   - tests check docs/scenes.md's key tables against it (tests/core/scene/test_keys.cpp).
// Adding a key is one row here plus its use: a line in the section reader that fills the Scene
// field (readers.cpp), and the code that reads that field.
//
// Keys belong to kinds of objects ("scene" is the top level; "shape.box" the keys of a box shape,
// a variant of "shape" chosen by its `type`). Key paths in messages are the document's
// ("bodies.0.shape.radius"); the table's path of a key is "kind.name".
#pragma once

#include "core/scene/contact_spec.hpp"
#include "core/springs.hpp"

#include <nlohmann/json.hpp>

#include <limits>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace harness {

enum class Integrator { symplectic_euler, implicit_euler };
// A body's shape (`shape.type`): each names a variant kind of the table, "shape.<word>".
enum class ShapeType { box, sphere, ellipsoid, cylinder, mesh };
// A surface shape's `fill` (the shapes layer's Fill: shell, volume).
enum class FillWord { shell, volume };
// A reference solver (`references.solvers`).
enum class Solver { cgal, fcl, ccd };
// A selection's `side`: a face of the rest bounding box.
enum class Side { minus_x, plus_x, minus_y, plus_y, minus_z, plus_z };
enum class Guard { refuse, substep };
enum class FrameFormat { vtp, vtu, vtk };

enum class KeyType {
  object,          // an object of kind `of`
  list,            // a list of objects of kind `of`, at least `lo` of them
  number,          // within [lo, hi] (lo excluded when lo_open)
  integer,         // within [lo, hi]
  boolean,
  string,          // at least `lo` characters
  word,            // one of `names`
  words,           // a list of distinct `names`
  vec3,            // [x, y, z]; each above `lo` when lo_open
  int3,            // three integers, each within [lo, hi]
  length_or_auto,  // "auto" (0 in the Scene) or a number within (lo, hi]
  force,           // a word of `names`, a number within [lo, hi], or an object of a kind `of`.RULE (force rules)
  always_true,     // present: must be true
  numbers,         // an object of named numbers (any names), each within [lo, hi]
};

enum class Presence {
  required,   // missing: an error
  defaulted,  // missing: `def`, written into the resolved scene
  optional,   // missing: absent (and absent from the resolved scene)
  computed,   // missing: a default the loader computes (the scene's name: the file's stem)
};

// How a key counts steps, for running a scene at dt / factor over the same physical time.
enum class StepCount {
  none,
  count,       // a number of steps: times factor (when > 0)
  first_step,  // a 1-based first step k: (k - 1) factor + 1 (when > 0)
  last_step,   // a 1-based last step k: k factor (when > 0; -1, "to the end", stays)
};

// How the schema writes a key: inline; a step count by reference ($defs steps, positive_steps:
// the key's range must be theirs); or shared by several kinds under $defs `def_name`.
enum class SchemaForm { inline_form, steps_ref, shared_def };

struct SceneKey {
  const char* kind = "";
  const char* name = "";
  KeyType type = KeyType::number;
  Presence presence = Presence::required;
  nlohmann::json def;  // Presence::defaulted
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  bool lo_open = false;
  std::vector<std::string> names;  // word, words
  const char* of = "";             // object, list, force: the kind of the value
  const char* unit = "";           // SI unit of a number ("" dimensionless or not a number)
  StepCount steps = StepCount::none;
  bool nullable = false;           // null accepted, meaning absent
  SchemaForm form = SchemaForm::inline_form;
  const char* def_name = "";       // SchemaForm::shared_def
  std::string doc;                 // the schema's description ("" none)
  nlohmann::json extra;            // schema constraints the fields do not express

  // The table's fluent setters (keys.cpp).
  SceneKey& required() { presence = Presence::required; return *this; }
  SceneKey& fallback(nlohmann::json v) { presence = Presence::defaulted, def = std::move(v); return *this; }
  SceneKey& optional() { presence = Presence::optional; return *this; }
  SceneKey& computed() { presence = Presence::computed; return *this; }
  SceneKey& range(double l, double h) { lo = l, hi = h; return *this; }
  SceneKey& above(double l, double h = std::numeric_limits<double>::infinity()) { lo = l, hi = h, lo_open = true; return *this; }
  SceneKey& in(std::vector<std::string> n) { names = std::move(n); return *this; }
  SceneKey& holding(const char* kind_of_value) { of = kind_of_value; return *this; }
  SceneKey& with_unit(const char* u) { unit = u; return *this; }
  SceneKey& counts(StepCount c) { steps = c; return *this; }
  SceneKey& null_ok() { nullable = true; return *this; }
  SceneKey& by_steps_ref() { form = SchemaForm::steps_ref; return *this; }
  SceneKey& shared(const char* d) { form = SchemaForm::shared_def, def_name = d; return *this; }
  SceneKey& described(std::string d) { doc = std::move(d); return *this; }
  SceneKey& schema(nlohmann::json e) { extra = std::move(e); return *this; }
};

// A kind of object: its keys are the rows of that kind, in the order the loader reads them.
struct SceneKind {
  const char* name = "";
  const char* def_name = "";   // "": written inline where it is used; else under $defs
  std::string doc;             // the schema's description of the object ("" none)
  nlohmann::json extra;        // schema constraints beyond its keys (oneOf, if/then/else, not)
  const char* variant_of = ""; // a variant: the kind it is a variant of, chosen by its `type`
};

const std::vector<SceneKey>& scene_keys();
// A default as descriptions and docs/scenes.md write it: a word bare, a number shortest (10
// significant digits), a list in brackets.
std::string default_text(const nlohmann::json& v);
// A key's description as the schema and editors show it: its row's prose, then the range and
// "Required" made from the row (range_text), then, for a key with a default that is not an
// object, "Default: X." (default_text of `def`): the prose never types the default itself.
std::string key_description(const SceneKey& k);
// A key's range as the descriptions write it, made from the row's bounds and type ("> 0, <= 1e6",
// "0 to 2e9", "1 to 1000 each", "non-empty", "at least 1"; "" for none): key_description appends
// it, "Required; " before it for a required key, so the prose never types a range either.
std::string range_text(const SceneKey& k);
const std::vector<SceneKind>& scene_kinds();
// The row of a key; throws std::logic_error for one the table does not have (a bug).
const SceneKey& scene_key(const std::string& kind, const std::string& name);
const SceneKind& scene_kind(const std::string& kind);
// The variants of a kind ("shape" -> "shape.box", ...), in table order, and the `type` word of each.
std::vector<std::pair<std::string, const SceneKind*>> scene_variants(const std::string& kind);

// The scene's words for the values of an enumeration, in the table's order; scene_word(e) its
// word (summary.json writes these).
template <class E>
const std::vector<std::pair<E, const char*>>& scene_words();
template <class E>
const char* scene_word(E e) {
  for (const auto& [v, n] : scene_words<E>())
    if (v == e) return n;
  return "?";
}
// The enumerator of a word of E's table; std::logic_error for a word the table lacks (the loader
// checks words against the key's names first: a bug).
template <class E>
E word_value(const std::string& word) {
  for (const auto& [v, n] : scene_words<E>())
    if (word == n) return v;
  throw std::logic_error("no enumerator for the word \"" + word + "\"");
}
template <class E>
std::vector<std::string> word_list() {
  std::vector<std::string> out;
  for (const auto& [v, n] : scene_words<E>()) out.emplace_back(n);
  return out;
}

}  // namespace harness
