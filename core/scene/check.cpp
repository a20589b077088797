#include "core/scene/check.hpp"

#include <cmath>
#include <limits>
#include <sstream>

namespace harness::scene_check {

void Ctx::fail(const std::string& path, const std::string& msg) const {
  throw InputError(file + ": " + (path.empty() ? std::string("(top level)") : path), msg);
}

std::string join(const std::string& path, const std::string& key) { return path.empty() ? key : path + "." + key; }
std::string join(const std::string& path, std::size_t i) { return join(path, std::to_string(i)); }

std::string type_name(const json& j) {
  if (j.is_number()) return "a number";
  if (j.is_string()) return "a string";
  if (j.is_boolean()) return "a boolean";
  if (j.is_array()) return "a list";
  if (j.is_object()) return "an object";
  return "null";
}

std::string fmt(double v) {
  std::ostringstream os;
  os.precision(10);
  os << v;
  return os.str();
}

double as_number(const Ctx& c, const std::string& path, const json& j) {
  if (!j.is_number()) c.fail(path, "expected a number, got " + type_name(j));
  const double v = j.get<double>();
  if (!std::isfinite(v)) c.fail(path, "number is not finite");
  return v;
}

long long as_integer(const Ctx& c, const std::string& path, const json& j) {
  const double v = as_number(c, path, j);
  // Above the range of long long (an unsigned JSON integer): get<long long>() would wrap
  // 18446744073709551615 to -1.
  constexpr auto kMax = static_cast<unsigned long long>(std::numeric_limits<long long>::max());
  if (j.is_number_unsigned() && j.get<unsigned long long>() > kMax)
    c.fail(path, "integer " + std::to_string(j.get<unsigned long long>()) + " out of range (above 9223372036854775807)");
  if (j.is_number_integer()) return j.get<long long>();
  if (v != std::floor(v) || std::fabs(v) > 9.0e15) c.fail(path, "expected an integer");
  return static_cast<long long>(v);
}

std::string as_string(const Ctx& c, const std::string& path, const json& j) {
  if (!j.is_string()) c.fail(path, "expected a string, got " + type_name(j));
  return j.get<std::string>();
}

bool as_bool(const Ctx& c, const std::string& path, const json& j) {
  if (!j.is_boolean()) c.fail(path, "expected true or false, got " + type_name(j));
  return j.get<bool>();
}

Vec3 as_vec3(const Ctx& c, const std::string& path, const json& j) {
  if (!j.is_array() || j.size() != 3) c.fail(path, "expected a list of 3 numbers");
  return Vec3(as_number(c, join(path, 0), j[0]), as_number(c, join(path, 1), j[1]), as_number(c, join(path, 2), j[2]));
}

const json& as_list(const Ctx& c, const std::string& path, const json& j) {
  if (!j.is_array()) c.fail(path, "expected a list, got " + type_name(j));
  return j;
}

Obj::Obj(const Ctx& c, const json& j, std::string path, json& out, const char* kind)
    : c_(c), j_(j), path_(std::move(path)), out_(out), kind_(kind) {
  if (!j.is_object()) c.fail(path_, "expected an object, got " + type_name(j));
  if (!out_.is_object()) out_ = json::object();
}

const json* Obj::get(const std::string& key) {
  seen_.insert(key);
  auto it = j_.find(key);
  return it == j_.end() ? nullptr : &*it;
}

const json& Obj::require(const std::string& key) {
  const json* v = get(key);
  if (!v) c_.fail(at(key), "missing required key");
  return *v;
}

namespace {
bool has_default(const SceneKey& k) { return k.presence == Presence::defaulted; }
}  // namespace

double Obj::number_in(const std::string& key, const SceneKey& k, const json* v) {
  double x;
  if (!v) {
    if (!has_default(k)) c_.fail(at(key), "missing required key");
    x = k.def.get<double>();
  } else {
    x = as_number(c_, at(key), *v);
  }
  if (x < k.lo || (k.lo_open && x == k.lo) || x > k.hi)
    c_.fail(at(key), "value " + fmt(x) + " out of range (" + (k.lo_open ? "> " : ">= ") + fmt(k.lo) +
                         (std::isfinite(k.hi) ? ", <= " + fmt(k.hi) : "") + ")");
  out_[key] = x;
  return x;
}

double Obj::number(const std::string& key) { return number_in(key, row(key), get(key)); }

long long Obj::integer(const std::string& key) {
  const SceneKey& k = row(key);
  const json* v = get(key);
  long long x;
  if (!v) {
    if (!has_default(k)) c_.fail(at(key), "missing required key");
    x = k.def.get<long long>();
  } else {
    x = as_integer(c_, at(key), *v);
  }
  const long long lo = std::isfinite(k.lo) ? static_cast<long long>(k.lo) : std::numeric_limits<long long>::min();
  const long long hi = std::isfinite(k.hi) ? static_cast<long long>(k.hi) : std::numeric_limits<long long>::max();
  if (x < lo || x > hi)
    c_.fail(at(key), "value " + std::to_string(x) + " out of range (" + std::to_string(lo) + " to " + std::to_string(hi) + ")");
  out_[key] = x;
  return x;
}

std::string Obj::choice(const std::string& key, const SceneKey& k, const std::vector<std::string>& allowed) {
  const json* v = get(key);
  std::string s;
  if (!v) {
    if (!has_default(k)) c_.fail(at(key), "missing required key");
    s = k.def.get<std::string>();
  } else {
    s = as_string(c_, at(key), *v);
  }
  bool ok = false;
  std::string list;
  for (const auto& a : allowed) {
    ok = ok || a == s;
    list += (list.empty() ? "\"" : ", \"") + a + "\"";
  }
  if (!ok) c_.fail(at(key), "unknown value \"" + s + "\" (expected one of " + list + ")");
  out_[key] = s;
  return s;
}

std::string Obj::word(const std::string& key) {
  const SceneKey& k = row(key);
  return choice(key, k, k.names);
}

Vec3 Obj::vec3(const std::string& key) {
  const SceneKey& k = row(key);
  const json* v = get(key);
  Vec3 x;
  if (!v) {
    if (!has_default(k)) c_.fail(at(key), "missing required key");
    x = Vec3(k.def[0].get<double>(), k.def[1].get<double>(), k.def[2].get<double>());
  } else {
    x = as_vec3(c_, at(key), *v);
  }
  out_[key] = {x.x(), x.y(), x.z()};
  if (k.lo_open && (x.array() <= k.lo).any()) c_.fail(at(key), key + " must be > " + fmt(k.lo));
  return x;
}

bool Obj::boolean(const std::string& key) {
  const SceneKey& k = row(key);
  const json* v = get(key);
  const bool b = v ? as_bool(c_, at(key), *v) : (k.type == KeyType::always_true || k.def.get<bool>());
  out_[key] = b;
  return b;
}

std::string Obj::string(const std::string& key, const std::string& computed) {
  const SceneKey& k = row(key);
  const json* v = get(key);
  if (!v && k.presence != Presence::defaulted && k.presence != Presence::computed) c_.fail(at(key), "missing required key");
  std::string s = v ? as_string(c_, at(key), *v) : k.presence == Presence::computed ? computed : k.def.get<std::string>();
  out_[key] = s;
  if (k.lo >= 1.0 && s.empty()) c_.fail(at(key), "empty " + key);
  return s;
}

double Obj::length_or_auto(const std::string& key) {
  const SceneKey& k = row(key);
  const json* v = get(key);
  if (!v || (v->is_string() && v->get<std::string>() == "auto")) {
    out_[key] = "auto";
    return 0.0;
  }
  return number_in(key, k, v);
}

void Obj::finish() const {
  for (auto it = j_.begin(); it != j_.end(); ++it)
    if (!seen_.count(it.key())) c_.fail(at(it.key()), "unknown key");
}

}  // namespace harness::scene_check
