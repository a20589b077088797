#include "core/scene/schema.hpp"

#include "core/scene/keys.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace harness {

using json = nlohmann::ordered_json;

namespace {

constexpr double kMaxSteps = 2e9;

// A number as the schema writes it: an integral value as an integer.
json num(double v) {
  if (std::isfinite(v) && v == std::floor(v) && std::fabs(v) < 9.0e15) return json(static_cast<long long>(v));
  return json(v);
}

json num_all(const json& v) {
  if (v.is_number_float()) return num(v.get<double>());
  if (!v.is_array()) return v;
  json out = json::array();
  for (const json& e : v) out.push_back(num_all(e));
  return out;
}

std::string ref(const std::string& def) { return "#/$defs/" + def; }

// Adds the constraints the table states beyond its fields (null: none).
void merge(json& s, const json& extra) {
  if (extra.is_object()) s.update(extra);
}

class Generator {
 public:
  json root() {
    const SceneKind& top = scene_kind("scene");
    json s = {{"$schema", "https://json-schema.org/draft/2020-12/schema"}, {"title", "harness scene"}};
    defs_["vec3"] = {{"description", "[x, y, z]: a list of 3 numbers."},
                     {"type", "array"},
                     {"items", {{"type", "number"}}},
                     {"minItems", 3},
                     {"maxItems", 3}};
    defs_["steps"] = {{"description", "A step count, 0 to 2e9."}, {"type", "integer"}, {"minimum", 0}, {"maximum", num(kMaxSteps)}};
    defs_["positive_steps"] = {
        {"description", "A step count, 1 to 2e9."}, {"type", "integer"}, {"minimum", 1}, {"maximum", num(kMaxSteps)}};
    s.update(object("scene"));
    s["description"] = top.doc;
    s["$defs"] = defs_;
    return s;
  }

 private:
  // An object of a kind: its keys, the required ones, no others (a kind with variants: its own
  // keys, then each variant's keys when `type` names it).
  json object(const std::string& kind_name) {
    const SceneKind& kind = scene_kind(kind_name);
    json s = json::object();
    if (!kind.doc.empty()) s["description"] = kind.doc;
    s["type"] = "object";
    keys_of(kind_name, s);
    const auto variants = scene_variants(kind_name);
    if (variants.empty()) {
      s["additionalProperties"] = false;
    } else {
      json all = json::array();
      for (const auto& [word, variant] : variants) {
        json then = json::object();
        then["properties"] = {{"type", true}};
        keys_of(variant->name, then);
        then["additionalProperties"] = false;
        all.push_back({{"if", {{"properties", {{"type", {{"const", word}}}}}, {"required", json::array({"type"})}}}, {"then", then}});
      }
      s["allOf"] = all;
    }
    merge(s, kind.extra);
    return s;
  }

  // The properties (and the required ones) of a kind's keys into s.
  void keys_of(const std::string& kind, json& s) {
    json required = json::array();
    if (!s.contains("properties")) s["properties"] = json::object();
    for (const SceneKey& k : scene_keys()) {
      if (kind != k.kind) continue;
      s["properties"][k.name] = key(k);
      if (k.presence == Presence::required) required.push_back(k.name);
    }
    if (!required.empty()) s["required"] = required;
  }

  // A kind written under $defs (once), or inline.
  json object_ref(const std::string& kind_name) {
    const SceneKind& kind = scene_kind(kind_name);
    if (!*kind.def_name) return object(kind_name);
    if (!defs_.contains(kind.def_name)) {
      defs_[kind.def_name] = json::object();  // reserved: a kind may refer to itself
      defs_[kind.def_name] = object(kind_name);
    }
    return {{"$ref", ref(kind.def_name)}};
  }

  json key(const SceneKey& k) {
    if (k.form != SchemaForm::shared_def) return plain(k);
    const json s = plain(k);
    if (!defs_.contains(k.def_name)) defs_[k.def_name] = s;
    if (defs_[k.def_name] != s)
      throw std::logic_error(std::string("the keys shared as $defs/") + k.def_name + " differ (core/scene/keys.cpp)");
    return {{"$ref", ref(k.def_name)}};
  }

  static void bounds(json& s, const SceneKey& k) {
    if (std::isfinite(k.lo)) s[k.lo_open ? "exclusiveMinimum" : "minimum"] = num(k.lo);
    if (std::isfinite(k.hi)) s["maximum"] = num(k.hi);
  }

  // A key of a scalar, word or array type: its schema into s.
  void typed(json& s, const SceneKey& k) {
    switch (k.type) {
      case KeyType::number:
        s["type"] = "number";
        bounds(s, k);
        break;
      case KeyType::integer:
        if (k.form == SchemaForm::steps_ref) {
          if (!(k.hi == kMaxSteps && (k.lo == 0.0 || k.lo == 1.0)))
            throw std::logic_error(std::string("step count ") + k.kind + "." + k.name + ": not the range of $defs steps");
          s["$ref"] = ref(k.lo == 0.0 ? "steps" : "positive_steps");
        } else {
          s["type"] = "integer";
          bounds(s, k);
        }
        break;
      case KeyType::boolean:
        s["type"] = "boolean";
        break;
      case KeyType::string:
        s["type"] = "string";
        if (k.lo >= 1.0) s["minLength"] = num(k.lo);
        break;
      case KeyType::word:
        if (k.names.size() == 1) s["const"] = k.names[0];
        else s["enum"] = k.names;
        break;
      case KeyType::words:
        s["type"] = "array";
        s["items"] = {{"enum", k.names}};
        s["uniqueItems"] = true;
        break;
      case KeyType::vec3:
        if (k.lo_open) {
          s["type"] = "array";
          s["items"] = {{"type", "number"}, {"exclusiveMinimum", num(k.lo)}};
          s["minItems"] = 3;
          s["maxItems"] = 3;
        } else {
          s["$ref"] = ref("vec3");
        }
        break;
      case KeyType::int3:
        s["type"] = "array";
        s["items"] = {{"type", "integer"}, {"minimum", num(k.lo)}, {"maximum", num(k.hi)}};
        s["minItems"] = 3;
        s["maxItems"] = 3;
        break;
      case KeyType::force:
      {  // the words, a number within the row's range, or an object of a kind k.of.RULE (one per rule)
        json any = json::array();
        for (const std::string& w : k.names) any.push_back({{"const", w}});
        any.push_back({{"type", "number"}, {"minimum", num(k.lo)}, {"maximum", num(k.hi)}});
        const std::string prefix = std::string(k.of) + ".";
        for (const SceneKind& kind : scene_kinds())
          if (std::string(kind.name).rfind(prefix, 0) == 0) any.push_back(object_ref(kind.name));
        s["anyOf"] = any;
        break;
      }
      case KeyType::always_true:
        s["const"] = true;
        break;
      case KeyType::numbers: {
        json item = {{"type", "number"}};
        bounds(item, k);
        s["type"] = "object";
        s["additionalProperties"] = item;
        break;
      }
      case KeyType::list:
        s["type"] = "array";
        s["items"] = object_ref(k.of);
        if (k.lo >= 1.0) s["minItems"] = num(k.lo);
        break;
      case KeyType::length_or_auto:
      case KeyType::object:
        throw std::logic_error("typed: not a scalar, word or array key");
    }
  }

  // "auto" or a length: the one $defs entry all such keys share (their range and default must be
  // its); the key's default is the definition's.
  json length_or_auto(json s, const SceneKey& k) {
    const json def = {{"anyOf", {{{"const", "auto"}}, {{"type", "number"}, {"exclusiveMinimum", num(k.lo)}, {"maximum", num(k.hi)}}}},
                      {"default", k.def}};
    if (!defs_.contains("length_or_auto")) defs_["length_or_auto"] = def;
    if (defs_["length_or_auto"] != def)
      throw std::logic_error(std::string("length_or_auto ") + k.kind + "." + k.name + ": another range or default");
    s["$ref"] = ref("length_or_auto");
    merge(s, k.extra);
    return s;
  }

  // An object key: its kind by reference or inline; an object's default ({}) is implied by its keys'.
  json object_key(json s, const SceneKey& k) {
    const SceneKind& kind = scene_kind(k.of);
    if (*kind.def_name) {
      s.update(object_ref(k.of));
    } else {
      json o = object(k.of);
      o.erase("description");
      s.update(o);
    }
    if (k.nullable) s["type"] = {"object", "null"};
    merge(s, k.extra);
    return s;
  }

  json plain(const SceneKey& k) {
    json s = json::object();
    if (const std::string d = key_description(k); !d.empty()) s["description"] = d;
    if (k.type == KeyType::length_or_auto) return length_or_auto(std::move(s), k);
    if (k.type == KeyType::object) return object_key(std::move(s), k);
    typed(s, k);
    if (k.presence == Presence::defaulted) s["default"] = num_all(k.def);
    merge(s, k.extra);
    return s;
  }

  json defs_ = json::object();
};

}  // namespace

nlohmann::ordered_json scene_schema() { return Generator().root(); }

namespace {

// One line when it fits (a value with its key, indented), else one member per line.
std::string compact(const json& j) {
  if (j.is_object()) {
    std::string s = "{";
    for (auto it = j.begin(); it != j.end(); ++it)
      s += (it == j.begin() ? "" : ", ") + json(it.key()).dump() + ": " + compact(it.value());
    return s + "}";
  }
  if (j.is_array()) {
    std::string s = "[";
    for (std::size_t i = 0; i < j.size(); ++i) s += (i ? ", " : "") + compact(j[i]);
    return s + "]";
  }
  return j.dump();
}

void pretty(std::string& out, const json& j, std::size_t indent, std::size_t used) {
  const std::string flat = compact(j);
  if ((!j.is_object() && !j.is_array()) || j.empty() || (indent > 0 && used + flat.size() <= 100)) {
    out += flat;
    return;
  }
  const std::string pad(indent + 2, ' ');
  out += j.is_object() ? "{\n" : "[\n";
  std::size_t n = 0;
  for (auto it = j.begin(); it != j.end(); ++it, ++n) {
    out += pad;
    std::string head;
    if (j.is_object()) head = json(it.key()).dump() + ": ";
    out += head;
    pretty(out, it.value(), indent + 2, pad.size() + head.size());
    out += n + 1 < j.size() ? ",\n" : "\n";
  }
  out += std::string(indent, ' ') + (j.is_object() ? "}" : "]");
}

}  // namespace

std::string scene_schema_text() {
  std::string out;
  pretty(out, scene_schema(), 0, 0);
  return out + "\n";
}

}  // namespace harness
