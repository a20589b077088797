// The loader's JSON checking toolkit (the section readers in readers.cpp use it): every error
// names the file and the key path; an object being read remembers the keys it read, so that the
// rest are unknown; each key's type, range, default and names come from its row of the key table
// (keys.hpp), and its resolved value (defaults written in) goes into the resolved scene.
#pragma once

#include "core/scene/keys.hpp"
#include "core/types.hpp"

#include <nlohmann/json.hpp>

#include <set>
#include <string>
#include <vector>

namespace harness::scene_check {

using nlohmann::json;

// Validation context: every error names the file and the key path.
struct Ctx {
  std::string file;
  [[noreturn]] void fail(const std::string& path, const std::string& msg) const;
};

std::string join(const std::string& path, const std::string& key);
std::string join(const std::string& path, std::size_t i);
std::string type_name(const json& j);
// The number as messages show it (10 significant digits).
std::string fmt(double v);

double as_number(const Ctx& c, const std::string& path, const json& j);
long long as_integer(const Ctx& c, const std::string& path, const json& j);
std::string as_string(const Ctx& c, const std::string& path, const json& j);
bool as_bool(const Ctx& c, const std::string& path, const json& j);
Vec3 as_vec3(const Ctx& c, const std::string& path, const json& j);
const json& as_list(const Ctx& c, const std::string& path, const json& j);

// An object of a kind being read; `out` receives its resolved value.
class Obj {
 public:
  Obj(const Ctx& c, const json& j, std::string path, json& out, const char* kind);
  const Ctx& ctx() const { return c_; }
  const std::string& path() const { return path_; }
  std::string at(const std::string& key) const { return join(path_, key); }
  bool has(const std::string& key) const { return j_.contains(key); }
  const json* get(const std::string& key);  // marks it read; null when absent
  const json& require(const std::string& key);
  json& out() { return out_; }
  // The row of a key of this object's kind.
  const SceneKey& row(const std::string& key) const { return scene_key(kind_, key); }

  // A key's value checked against its row (type, range, names), its default when absent (a
  // required key absent is an error), written into the resolved object.
  double number(const std::string& key);
  long long integer(const std::string& key);
  std::string word(const std::string& key);
  // A word of `names` (another key's) for this key, its default from this key's row.
  std::string word_in(const std::string& key, const std::vector<std::string>& names) { return choice(key, row(key), names); }
  template <class E>
  E word(const std::string& key) {
    const std::string w = word(key);
    for (const auto& [v, n] : scene_words<E>())
      if (w == n) return v;
    return scene_words<E>().front().first;
  }
  Vec3 vec3(const std::string& key);
  bool boolean(const std::string& key);
  // `computed`: the default of a Presence::computed key.
  std::string string(const std::string& key, const std::string& computed = "");
  // length_or_auto: "auto" (absent or the word) as 0.
  double length_or_auto(const std::string& key);

  // Every key not read is unknown.
  void finish() const;

 private:
  double number_in(const std::string& key, const SceneKey& k, const json* v);
  std::string choice(const std::string& key, const SceneKey& k, const std::vector<std::string>& allowed);

  const Ctx& c_;
  const json& j_;
  std::string path_;
  json& out_;
  const char* kind_;
  std::set<std::string> seen_;
};

}  // namespace harness::scene_check
