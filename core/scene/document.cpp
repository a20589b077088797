// The scene document before validation: JSON text parsed (line and column of syntax errors,
// duplicate keys refused), files read, and the edits a command line or the reference levels make
// (--set, --steps, step rescaling for --dt-divide and --dt, whose step-counting keys come from the
// key table). It is validated once, into a Scene (readers.cpp).
#include "core/scene/scene.hpp"

#include "core/scene/check.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>

namespace harness {

using nlohmann::json;

namespace {

std::string type_name(const json& j) { return scene_check::type_name(j); }

}  // namespace

namespace {

// Line and column (1-based) of a byte offset in text.
std::string line_col(const std::string& text, std::size_t byte) {
  std::size_t line = 1, col = 1;
  for (std::size_t i = 0; i + 1 < byte && i < text.size(); ++i) {
    if (text[i] == '\n') {
      ++line;
      col = 1;
    } else {
      ++col;
    }
  }
  return std::to_string(line) + ":" + std::to_string(col);
}

// Rejects duplicate keys in one object, which JSON parsers otherwise silently merge.
struct DuplicateKeyCheck {
  std::vector<std::set<std::string>> stack;
  std::string dup;
  bool operator()(int depth, json::parse_event_t ev, json& parsed) {
    (void)depth;
    if (ev == json::parse_event_t::object_start) stack.emplace_back();
    else if (ev == json::parse_event_t::object_end) stack.pop_back();
    else if (ev == json::parse_event_t::key && !stack.empty()) {
      const std::string k = parsed.get<std::string>();
      if (!stack.back().insert(k).second && dup.empty()) dup = k;
    }
    return true;
  }
};
}  // namespace

void apply_override(json& doc, const std::string& key, const std::string& value_json) {
  const std::string where = "--set " + key;
  json value;
  try {
    value = json::parse(value_json);
  } catch (const json::parse_error& e) {
    // A bare word (plane, auto) is taken as a JSON string, as --grid does, so shells need no
    // extra quotes; anything else that is not JSON is an error.
    bool word = !value_json.empty() && (std::isalpha(static_cast<unsigned char>(value_json[0])) || value_json[0] == '_');
    for (char ch : value_json) word = word && (std::isalnum(static_cast<unsigned char>(ch)) || ch == '_');
    if (!word) throw InputError(where, "value is not valid JSON (" + value_json + ")");
    value = value_json;
  } catch (const json::out_of_range&) {
    // Number overflow ("1e999"): escaped as a json exception (exit 1 instead of 2).
    throw InputError(where, "malformed JSON: number overflow in the value (" + value_json + ")");
  }
  if (key.empty()) throw InputError(where, "empty key");
  json* node = &doc;
  std::size_t start = 0;
  while (true) {
    const std::size_t dot = key.find('.', start);
    const std::string part = key.substr(start, dot == std::string::npos ? std::string::npos : dot - start);
    if (part.empty()) throw InputError(where, "empty component in key path");
    json* next = nullptr;
    if (node->is_array()) {
      char* end = nullptr;
      const long idx = std::strtol(part.c_str(), &end, 10);
      if (*end != '\0' || idx < 0) throw InputError(where, "\"" + part + "\" is not a list index");
      if (static_cast<std::size_t>(idx) >= node->size())
        throw InputError(where, "index " + part + " out of range (list has " + std::to_string(node->size()) + " items)");
      next = &(*node)[static_cast<std::size_t>(idx)];
    } else if (node->is_object() || node->is_null()) {
      if (node->is_null()) *node = json::object();
      next = &(*node)[part];
    } else {
      throw InputError(where, "cannot descend into a " + type_name(*node));
    }
    node = next;
    if (dot == std::string::npos) break;
    start = dot + 1;
  }
  // Moved, not copied: the copy recurses once per nesting level, and a deeply nested value
  // ("[[[[...]]]]", 200000 levels) exhausted the stack.
  *node = std::move(value);
}

SceneSource parse_scene_source(const std::string& text, const std::string& file) {
  json doc;
  DuplicateKeyCheck dup;
  try {
    doc = json::parse(text, [&dup](int d, json::parse_event_t e, json& p) { return dup(d, e, p); });
  } catch (const json::parse_error& e) {
    std::string msg = e.what();
    // nlohmann's message: "[json.exception.parse_error.101] parse error at line L, column C: ..."
    const auto colon = msg.find(": ", msg.find("column"));
    if (colon != std::string::npos) msg = msg.substr(colon + 2);
    throw InputError(file + ":" + line_col(text, e.byte), "malformed JSON: " + msg);
  } catch (const json::out_of_range& e) {
    // Number overflow ("1e999"): nlohmann gives no position, so find the token in the text.
    std::string msg = e.what();
    const auto q1 = msg.find('\''), q2 = msg.rfind('\'');
    std::string where = file;
    if (q1 != std::string::npos && q2 > q1) {
      const auto at = text.find(msg.substr(q1 + 1, q2 - q1 - 1));
      if (at != std::string::npos) where += ":" + line_col(text, at + 1);
    }
    const auto sp = msg.find("] ");
    throw InputError(where, "malformed JSON: " + (sp == std::string::npos ? msg : msg.substr(sp + 2)));
  }
  if (!dup.dup.empty()) throw InputError(file, "duplicate key \"" + dup.dup + "\" in an object");
  std::string dir = std::filesystem::path(file).parent_path().string();
  if (dir.empty()) dir = ".";
  return SceneSource{std::move(doc), file, dir};
}


std::vector<std::pair<std::string, std::string>> steps_overrides(long long steps) {
  return {{"time.steps", std::to_string(steps)}, {"time.settle", "null"}};
}

namespace {

// A JSON integer, or a number with an integral value (the loader accepts both), as long long.
bool integral(const json& v, long long& out) {
  if (v.is_number_unsigned()) {
    if (v.get<unsigned long long>() > static_cast<unsigned long long>(std::numeric_limits<long long>::max())) return false;
    out = v.get<long long>();
    return true;
  }
  if (v.is_number_integer()) {
    out = v.get<long long>();
    return true;
  }
  if (!v.is_number_float()) return false;
  const double d = v.get<double>();
  if (!std::isfinite(d) || d != std::floor(d) || std::fabs(d) > 9.0e15) return false;
  out = static_cast<long long>(d);
  return true;
}

// Whether a kind (or what it holds) has a step count whose default is positive: a missing object
// of it must be made to carry that default, scaled.
bool positive_step_default(const std::string& kind) {
  for (const SceneKey& k : scene_keys())
    if (kind == k.kind && k.steps != StepCount::none && k.presence == Presence::defaulted && k.def.get<long long>() > 0)
      return true;
  return false;
}

// A step count times `ratio` (steps at the new dt per step at the old one): exact for a whole
// ratio; otherwise rounded to the nearest count, at least 1 (a first step: step k covers the new
// steps from (k - 1) ratio + 1 on).
long long scaled(long long n, double ratio, bool first_step) {
  const double r = ratio;
  const double v = first_step ? static_cast<double>(n - 1) * r + 1.0 : static_cast<double>(n) * r;
  return std::max<long long>(1, std::llround(v));
}

// A count of the scene's forcing (a driver's steps, a load's or a pressure's ramp) that the ratio
// does not carry to a whole number of steps: the forcing changes (a driver's travel, a ramp's
// length) by the rounding; said (path, old count, exact value, new count) so that the run can warn.
// Counts of running and measuring (time.steps, the window, settling, references.every, frames) are
// rounded without a word: they change what is recorded, not the scene.
bool forcing_kind(const std::string& kind) { return kind == "driver" || kind == "load" || kind == "pressure"; }

void note_rounding(std::vector<std::string>* notes, const std::string& path, long long n, double exact, long long m) {
  if (!notes || std::fabs(exact - static_cast<double>(m)) <= 1e-9 * std::max(1.0, exact)) return;
  char b[200];
  std::snprintf(b, sizeof b, "%lld steps at the scene's time.dt are %.6g at --dt, rounded to %lld (%+.2g %%)", n, exact, m,
                100.0 * (static_cast<double>(m) - exact) / exact);
  notes->push_back(path + ": " + b);
}

void scale_count(json& obj, const SceneKey& k, double ratio, const std::string& path, std::vector<std::string>* notes) {
  auto it = obj.find(k.name);
  if (it == obj.end()) {
    // Left out: its default counts steps too.
    if (k.presence != Presence::defaulted || k.def.get<long long>() <= 0) return;
    it = obj.emplace(k.name, k.def).first;
  }
  long long n = 0;
  if (!integral(*it, n) || n <= 0 || static_cast<double>(n) * ratio > 9.0e15) return;  // the loader's to report
  const long long whole = std::llround(ratio);
  if (static_cast<double>(whole) == ratio) {  // whole: exact integer arithmetic
    *it = k.steps == StepCount::first_step ? (n - 1) * whole + 1 : n * whole;
  } else {
    const bool first = k.steps == StepCount::first_step;
    const long long m = scaled(n, ratio, first);
    if (forcing_kind(k.kind))
      note_rounding(notes, path + k.name, n, first ? static_cast<double>(n - 1) * ratio + 1.0 : static_cast<double>(n) * ratio, m);
    *it = m;
  }
}

// `path`: the key path of `obj` with its trailing dot ("" at the top); `notes` (may be null): the
// counts that were rounded (note_rounding).
void rescale_object(json& obj, const std::string& kind, double factor, const std::string& path = "",
                    std::vector<std::string>* notes = nullptr) {
  for (const SceneKey& k : scene_keys()) {
    if (kind != k.kind) continue;
    if (k.steps != StepCount::none) {
      scale_count(obj, k, factor, path, notes);
    } else if (k.type == KeyType::object) {
      auto it = obj.find(k.name);
      if (it == obj.end() && k.presence == Presence::defaulted && positive_step_default(k.of))
        it = obj.emplace(k.name, json::object()).first;
      if (it != obj.end() && it->is_object()) rescale_object(*it, k.of, factor, path + k.name + ".", notes);
    } else if (k.type == KeyType::list) {
      auto it = obj.find(k.name);
      if (it != obj.end() && it->is_array())
        for (std::size_t i = 0; i < it->size(); ++i)
          if ((*it)[i].is_object())
            rescale_object((*it)[i], k.of, factor, path + k.name + "." + std::to_string(i) + ".", notes);
    }
  }
}

}  // namespace

void rescale_steps(json& doc, int factor) {
  if (factor < 1) throw InputError("--dt-divide", "must be >= 1");
  if (factor == 1 || !doc.is_object()) return;
  auto t = doc.find("time");
  if (t != doc.end() && t->is_object()) {
    auto dt = t->find("dt");
    if (dt != t->end() && dt->is_number()) *dt = dt->get<double>() / factor;
  }
  rescale_object(doc, "scene", factor);
}

std::vector<std::string> rescale_to_dt(json& doc, double dt) {
  std::vector<std::string> notes;
  if (!(dt > 0.0) || !std::isfinite(dt)) throw InputError("--dt", "must be a time step > 0, s");
  if (!doc.is_object() || !doc.contains("time") || !doc["time"].is_object() || !doc["time"].contains("dt") ||
      !doc["time"]["dt"].is_number())
    return notes;  // the loader reports the scene's time.dt
  const double scene_dt = doc["time"]["dt"].get<double>();
  if (!(scene_dt > 0.0) || !std::isfinite(scene_dt)) return notes;  // the loader reports it
  const double ratio = scene_dt / dt;
  const double n = std::round(ratio);
  if (!(ratio <= 1e6) || !(ratio >= 1e-6))
    throw InputError("--dt", scene_check::fmt(dt) + " s is more than a million times the scene's time.dt (" +
                                 scene_check::fmt(scene_dt) + " s) or less than a millionth of it");
  if (n >= 1.0 && std::fabs(ratio - n) <= 1e-9 * ratio) {
    rescale_steps(doc, static_cast<int>(n));  // a whole divisor: exact
  } else {
    rescale_object(doc, "scene", ratio, "", &notes);  // any other: every count rounded, the roundings said
  }
  doc["time"]["dt"] = dt;
  return notes;
}

Scene rescale_dt(const Scene& scene, int factor) {
  if (factor < 1) throw InputError(scene.file + ": time.dt", "the dt divisor must be >= 1");
  json doc = scene.resolved;
  rescale_steps(doc, factor);
  return scene_from_json(doc, scene.file, scene.dir);
}

std::string read_text_file(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw InputError(path, "no such file");
  if (std::filesystem::is_directory(path, ec)) throw InputError(path, "is a directory, not a file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "cannot open for reading");
  std::ostringstream ss;
  ss << in.rdbuf();
  if (in.bad()) throw InputError(path, "read error");
  return ss.str();
}

SceneSource read_scene_source(const std::string& path) { return parse_scene_source(read_text_file(path), path); }

Scene scene_from_source(const SceneSource& src) { return scene_from_json(src.doc, src.file, src.dir); }

Scene parse_scene(const std::string& text, const std::string& file,
                  const std::vector<std::pair<std::string, std::string>>& overrides) {
  SceneSource src = parse_scene_source(text, file);
  for (const auto& [k, v] : overrides) apply_override(src.doc, k, v);
  return scene_from_source(src);
}

Scene load_scene(const std::string& path,
                 const std::vector<std::pair<std::string, std::string>>& overrides) {
  return parse_scene(read_text_file(path), path, overrides);
}

}  // namespace harness
