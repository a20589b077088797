#include "core/scene.hpp"

#include "core/collision/collision.hpp"
#include "core/effects/effects.hpp"
#include "core/shapes/shapes.hpp"

#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>

namespace harness {

using nlohmann::json;

std::vector<std::pair<EffectFlag, const char*>> effect_names() {
  std::vector<std::pair<EffectFlag, const char*>> names;
  for (const EffectEntry& e : effect_table()) names.emplace_back(static_cast<EffectFlag>(e.flag), e.name);
  return names;
}

namespace {

// Validation context: every error names the file and the key path.
struct Ctx {
  std::string file;
  [[noreturn]] void fail(const std::string& path, const std::string& msg) const {
    throw InputError(file + ": " + (path.empty() ? std::string("(top level)") : path), msg);
  }
};

std::string join(const std::string& path, const std::string& key) {
  return path.empty() ? key : path + "." + key;
}
std::string join(const std::string& path, std::size_t i) { return join(path, std::to_string(i)); }

std::string type_name(const json& j) {
  if (j.is_number()) return "a number";
  if (j.is_string()) return "a string";
  if (j.is_boolean()) return "a boolean";
  if (j.is_array()) return "a list";
  if (j.is_object()) return "an object";
  return "null";
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
    c.fail(path, "integer " + std::to_string(j.get<unsigned long long>()) +
                     " out of range (above 9223372036854775807)");
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
  return Vec3(as_number(c, join(path, 0), j[0]), as_number(c, join(path, 1), j[1]),
              as_number(c, join(path, 2), j[2]));
}

std::string fmt(double v) {
  std::ostringstream os;
  os.precision(10);
  os << v;
  return os.str();
}

// An object being validated: remembers which keys were read, so that the rest are unknown.
// `out` receives the resolved value (defaults written in).
class Obj {
 public:
  Obj(const Ctx& c, const json& j, std::string path, json& out)
      : c_(c), j_(j), path_(std::move(path)), out_(out) {
    if (!j.is_object()) c.fail(path_, "expected an object, got " + type_name(j));
    if (!out_.is_object()) out_ = json::object();
  }
  const std::string& path() const { return path_; }
  std::string at(const std::string& key) const { return join(path_, key); }
  bool has(const std::string& key) const { return j_.contains(key); }
  const json* get(const std::string& key) {
    seen_.insert(key);
    auto it = j_.find(key);
    return it == j_.end() ? nullptr : &*it;
  }
  const json& require(const std::string& key) {
    const json* v = get(key);
    if (!v) c_.fail(at(key), "missing required key");
    return *v;
  }

  double number(const std::string& key, std::optional<double> def, double lo, double hi,
                bool lo_open = false) {
    const json* v = get(key);
    double x;
    if (!v) {
      if (!def) c_.fail(at(key), "missing required key");
      x = *def;
    } else {
      x = as_number(c_, at(key), *v);
    }
    if (x < lo || (lo_open && x == lo) || x > hi)
      c_.fail(at(key), "value " + fmt(x) + " out of range (" + (lo_open ? "> " : ">= ") + fmt(lo) +
                           (hi < std::numeric_limits<double>::max() ? ", <= " + fmt(hi) : "") + ")");
    out_[key] = x;
    return x;
  }
  long long integer(const std::string& key, std::optional<long long> def, long long lo,
                    long long hi) {
    const json* v = get(key);
    long long x;
    if (!v) {
      if (!def) c_.fail(at(key), "missing required key");
      x = *def;
    } else {
      x = as_integer(c_, at(key), *v);
    }
    if (x < lo || x > hi)
      c_.fail(at(key), "value " + std::to_string(x) + " out of range (" + std::to_string(lo) +
                           " to " + std::to_string(hi) + ")");
    out_[key] = x;
    return x;
  }
  std::string choice(const std::string& key, std::optional<std::string> def,
                     const std::vector<std::string>& allowed) {
    const json* v = get(key);
    std::string s;
    if (!v) {
      if (!def) c_.fail(at(key), "missing required key");
      s = *def;
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
  Vec3 vec3(const std::string& key, std::optional<Vec3> def) {
    const json* v = get(key);
    Vec3 x;
    if (!v) {
      if (!def) c_.fail(at(key), "missing required key");
      x = *def;
    } else {
      x = as_vec3(c_, at(key), *v);
    }
    out_[key] = {x.x(), x.y(), x.z()};
    return x;
  }
  bool boolean(const std::string& key, bool def) {
    const json* v = get(key);
    const bool b = v ? as_bool(c_, at(key), *v) : def;
    out_[key] = b;
    return b;
  }
  std::string string(const std::string& key, std::optional<std::string> def) {
    const json* v = get(key);
    if (!v && !def) c_.fail(at(key), "missing required key");
    std::string s = v ? as_string(c_, at(key), *v) : *def;
    out_[key] = s;
    return s;
  }
  json& out() { return out_; }
  // Every key not read is unknown.
  void finish() const {
    for (auto it = j_.begin(); it != j_.end(); ++it)
      if (!seen_.count(it.key())) c_.fail(at(it.key()), "unknown key");
  }

 private:
  const Ctx& c_;
  const json& j_;
  std::string path_;
  json& out_;
  std::set<std::string> seen_;
};

const json& as_list(const Ctx& c, const std::string& path, const json& j) {
  if (!j.is_array()) c.fail(path, "expected a list, got " + type_name(j));
  return j;
}

Selection read_selection(const Ctx& c, const json& j, const std::string& path, json& out) {
  Obj o(c, j, path, out);
  Selection s;
  s.path = path;
  int n = 0;
  for (const char* k : {"side", "box", "all"}) n += o.has(k) ? 1 : 0;
  if (n != 1) c.fail(path, "a selection needs exactly one of \"side\", \"box\", \"all\"");
  if (o.has("side")) {
    const std::string side = o.choice("side", std::nullopt, {"-x", "+x", "-y", "+y", "-z", "+z"});
    s.kind = Selection::side;
    s.sign = side[0] == '-' ? -1 : 1;
    s.axis = side[1] - 'x';
  } else if (o.has("box")) {
    s.kind = Selection::box;
    Obj b(c, *o.get("box"), o.at("box"), o.out()["box"]);
    s.min = b.vec3("min", std::nullopt);
    s.max = b.vec3("max", std::nullopt);
    b.finish();
    if ((s.min.array() > s.max.array()).any()) c.fail(o.at("box"), "min exceeds max");
  } else {
    s.kind = Selection::all;
    if (!o.boolean("all", true)) c.fail(o.at("all"), "\"all\" must be true");
  }
  o.finish();
  return s;
}

constexpr double kBig = std::numeric_limits<double>::max();

ShapeSpec read_shape(const Ctx& c, const json& j, const std::string& path, json& out,
                     const std::string& dir) {
  Obj o(c, j, path, out);
  ShapeSpec s;
  s.type = o.choice("type", std::nullopt, {"box", "sphere", "ellipsoid", "cylinder", "mesh"});
  auto fill = [&]() {
    s.volume_fill = o.choice("fill", std::string("shell"), {"shell", "volume"}) == "volume";
  };
  if (s.type == "box") {
    s.min = o.vec3("min", std::nullopt);
    s.max = o.vec3("max", std::nullopt);
    if (!(s.min.array() < s.max.array()).all()) c.fail(o.at("max"), "max must exceed min on every axis");
    const json* cells = o.get("cells");
    if (!cells) c.fail(o.at("cells"), "missing required key");
    if (!cells->is_array() || cells->size() != 3) c.fail(o.at("cells"), "expected a list of 3 integers");
    long long total = 1;
    for (int a = 0; a < 3; ++a) {
      const long long n = as_integer(c, join(o.at("cells"), a), (*cells)[a]);
      if (n < 1 || n > 1000) c.fail(join(o.at("cells"), a), "value out of range (1 to 1000)");
      s.cells[a] = static_cast<int>(n);
      total *= (n + 1);
    }
    if (total > 20000000) c.fail(o.at("cells"), "too many nodes (" + std::to_string(total) + " > 2e7)");
    o.out()["cells"] = {s.cells[0], s.cells[1], s.cells[2]};
    if (o.has("fill") && o.choice("fill", std::nullopt, {"shell", "volume"}) != "volume")
      c.fail(o.at("fill"), "a box lattice is always volumetric");
    s.volume_fill = true;
    o.out()["fill"] = "volume";
  } else if (s.type == "sphere" || s.type == "ellipsoid") {
    s.center = o.vec3("center", Vec3::Zero());
    if (s.type == "sphere") {
      s.radius = o.number("radius", std::nullopt, 0.0, kBig, true);
      s.radii = Vec3::Constant(s.radius);
    } else {
      s.radii = o.vec3("radii", std::nullopt);
      if ((s.radii.array() <= 0.0).any()) c.fail(o.at("radii"), "radii must be > 0");
    }
    s.subdivisions = static_cast<int>(o.integer("subdivisions", 2, 0, kMaxSubdivisions));
    fill();
  } else if (s.type == "cylinder") {
    s.center = o.vec3("center", Vec3::Zero());
    s.axis = o.vec3("axis", Vec3::UnitZ());
    if (s.axis.norm() < 1e-12) c.fail(o.at("axis"), "axis must be non-zero");
    s.radius = o.number("radius", std::nullopt, 0.0, kBig, true);
    s.length = o.number("length", std::nullopt, 0.0, kBig, true);
    s.segments = static_cast<int>(o.integer("segments", 16, 3, 100000));
    s.rings = static_cast<int>(o.integer("rings", 4, 1, 100000));
    if (static_cast<long long>(s.segments) * (s.rings + 1) > 20000000)
      c.fail(o.at("rings"), "too many nodes (segments * (rings + 1) > 2e7)");
    fill();
  } else {
    const std::string p = o.string("path", std::nullopt);
    if (p.empty()) c.fail(o.at("path"), "empty path");
    std::filesystem::path fp(p);
    s.path = fp.is_absolute() ? p : (std::filesystem::path(dir) / fp).lexically_normal().string();
    s.scale = o.number("scale", 1.0, 0.0, kBig, true);
    s.translate = o.vec3("translate", Vec3::Zero());
    fill();
  }
  o.finish();
  return s;
}

Material read_material(const Ctx& c, const json* j, const std::string& path, json& out, bool shell) {
  static const json empty = json::object();
  Obj o(c, j ? *j : empty, path, out);
  Material m;
  m.density = o.number("density", 1000.0, 0.0, kBig, true);
  if (o.has("stiffness") && o.has("youngs_modulus"))
    c.fail(path, "both \"stiffness\" (N/m per spring) and \"youngs_modulus\" (Pa) are given: choose one");
  if (o.has("youngs_modulus")) {
    m.youngs_modulus = o.number("youngs_modulus", std::nullopt, 0.0, kBig, true);
    if (shell) m.thickness = o.number("thickness", std::nullopt, 0.0, kBig, true);
  } else {
    m.stiffness = o.number("stiffness", 100.0, 0.0, kBig, true);
  }
  if (o.has("thickness") && !(shell && m.youngs_modulus > 0.0))
    c.fail(o.at("thickness"), shell ? "a thickness goes with \"youngs_modulus\"" : "only a shell (fill \"shell\") has a thickness");
  const std::string law = o.choice("law", std::string("linear"), {"linear", "cubic", "exponential"});
  m.law = law == "linear" ? SpringLawKind::linear
                          : law == "cubic" ? SpringLawKind::cubic : SpringLawKind::exponential;
  m.nonlinearity = o.number("nonlinearity", 0.0, 0.0, 1e6);
  m.damping = o.number("damping", 0.0, 0.0, kBig);
  m.mass_damping = o.number("mass_damping", 0.0, 0.0, kBig);
  o.finish();
  return m;
}

BodySpec read_body(const Ctx& c, const json& j, const std::string& path, json& out,
                   const std::string& dir) {
  Obj o(c, j, path, out);
  BodySpec b;
  b.path = path;
  b.name = o.string("name", std::nullopt);
  if (b.name.empty()) c.fail(o.at("name"), "empty name");
  b.shape = read_shape(c, o.require("shape"), o.at("shape"), o.out()["shape"], dir);
  b.material = read_material(c, o.get("material"), o.at("material"), o.out()["material"], !b.shape.volume_fill);
  b.velocity = o.vec3("velocity", Vec3::Zero());
  o.out()["pins"] = json::array();
  if (const json* pins = o.get("pins")) {
    as_list(c, o.at("pins"), *pins);
    for (std::size_t i = 0; i < pins->size(); ++i) {
      json r;
      b.pins.push_back(read_selection(c, (*pins)[i], join(o.at("pins"), i), r));
      o.out()["pins"].push_back(r);
    }
  }
  o.out()["drivers"] = json::array();
  if (const json* drv = o.get("drivers")) {
    as_list(c, o.at("drivers"), *drv);
    for (std::size_t i = 0; i < drv->size(); ++i) {
      json r;
      Obj d(c, (*drv)[i], join(o.at("drivers"), i), r);
      DriverSpec ds;
      json sel;
      ds.select = read_selection(c, d.require("select"), d.at("select"), sel);
      d.out()["select"] = sel;
      ds.velocity = d.vec3("velocity", std::nullopt);
      ds.from_step = static_cast<int>(d.integer("from_step", 0, 0, 2000000000));
      ds.to_step = static_cast<int>(d.integer("to_step", -1, -1, 2000000000));
      if (ds.to_step >= 0 && ds.to_step < ds.from_step)
        c.fail(d.at("to_step"), "to_step is before from_step");
      d.finish();
      b.drivers.push_back(ds);
      o.out()["drivers"].push_back(r);
    }
  }
  o.out()["loads"] = json::array();
  if (const json* loads = o.get("loads")) {
    as_list(c, o.at("loads"), *loads);
    for (std::size_t i = 0; i < loads->size(); ++i) {
      json r;
      Obj l(c, (*loads)[i], join(o.at("loads"), i), r);
      LoadSpec ls;
      json sel;
      ls.select = read_selection(c, l.require("select"), l.at("select"), sel);
      l.out()["select"] = sel;
      ls.force = l.vec3("force", std::nullopt);
      ls.ramp_steps = static_cast<int>(l.integer("ramp_steps", 0, 0, 2000000000));
      l.finish();
      b.loads.push_back(ls);
      o.out()["loads"].push_back(r);
    }
  }
  if (const json* p = o.get("pressure")) {
    Obj po(c, *p, o.at("pressure"), o.out()["pressure"]);
    b.pressure.present = true;
    b.pressure.from = po.number("from", 0.0, -1e9, 1e9);
    b.pressure.to = po.number("to", std::nullopt, -1e9, 1e9);
    b.pressure.ramp_steps = static_cast<int>(po.integer("ramp_steps", 0, 0, 2000000000));
    po.finish();
  }
  o.finish();
  return b;
}

}  // namespace

namespace {

// The enum value a scene word names, from a (value, name) table.
template <class E>
E pick(Obj& o, const std::string& key, const std::string& def, const std::vector<std::pair<E, const char*>>& table) {
  std::vector<std::string> names;
  for (const auto& [v, n] : table) names.emplace_back(n);
  const std::string word = o.choice(key, def, names);
  for (const auto& [v, n] : table)
    if (word == n) return v;
  return table.front().first;
}

void read_time(const Ctx& c, Obj& top, Scene& s) {
  Obj t(c, top.require("time"), "time", s.resolved["time"]);
  s.dt = t.number("dt", std::nullopt, 0.0, 1e3, true);
  s.steps = static_cast<int>(t.integer("steps", std::nullopt, 0, 2000000000));
  s.integrator = pick<Integrator>(t, "integrator", "symplectic_euler",
                                  {{Integrator::symplectic_euler, "symplectic_euler"},
                                   {Integrator::implicit_euler, "implicit_euler"}});
  s.guard = pick<Guard>(t, "guard", "refuse", {{Guard::refuse, "refuse"}, {Guard::substep, "substep"}});
  s.window = static_cast<int>(t.integer("window", 1000, 1, 2000000000));
  if (const json* st = t.get("settle"); st && !st->is_null()) {  // null: no settling (--steps)
    Obj o(c, *st, t.at("settle"), t.out()["settle"]);
    s.settle.present = true;
    s.settle.tolerance = o.number("tolerance", 1e-3, 0.0, 1.0, true);
    s.settle.max_steps = static_cast<int>(o.integer("max_steps", std::nullopt, 1, 2000000000));
    o.finish();
  }
  t.finish();
}

void read_effects(const Ctx& c, Obj& top, Scene& s) {
  json& R = s.resolved;
  R["effects"] = json::array();
  if (const json* eff = top.get("effects")) {
    as_list(c, "effects", *eff);
    for (std::size_t i = 0; i < eff->size(); ++i) {
      const std::string e = as_string(c, join("effects", i), (*eff)[i]);
      unsigned bit = 0;
      std::string list;
      for (const auto& [b, n] : effect_names()) {
        if (e == n) bit = b;
        list += (list.empty() ? "" : ", ") + std::string(n);
      }
      if (!bit) c.fail(join("effects", i), "unknown effect \"" + e + "\" (expected one of " + list + ")");
      if (s.effects & bit) c.fail(join("effects", i), "effect \"" + e + "\" listed twice");
      s.effects |= bit;
    }
  }
  for (const auto& [b, n] : effect_names())
    if (s.effects & b) R["effects"].push_back(n);
}

void read_bodies(const Ctx& c, Obj& top, Scene& s, const std::string& dir) {
  const json& bodies = as_list(c, "bodies", top.require("bodies"));
  if (bodies.empty()) c.fail("bodies", "at least one body is needed");
  s.resolved["bodies"] = json::array();
  std::set<std::string> names;
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    json r;
    BodySpec b = read_body(c, bodies[i], join("bodies", i), r, dir);
    if (!names.insert(b.name).second) c.fail(join(join("bodies", i), "name"), "duplicate body name \"" + b.name + "\"");
    s.resolved["bodies"].push_back(r);
    s.bodies.push_back(std::move(b));
  }
}

ContactPairSpec read_contact(const Ctx& c, const json& j, const std::string& path, json& r, const Scene& s) {
  Obj o(c, j, path, r);
  ContactPairSpec p;
  p.path = path;
  p.host = o.string("host", std::nullopt);
  p.guest = o.string("guest", std::nullopt);
  // The one check of the names a scene gives; the spec gets the bodies' indices (the world lays
  // the bodies out in scene order).
  auto index = [&](const std::string& name) {
    for (std::size_t i = 0; i < s.bodies.size(); ++i)
      if (s.bodies[i].name == name) return static_cast<int>(i);
    return -1;
  };
  ContactSpec& cs = p.spec;
  cs.host = index(p.host);
  cs.guest = index(p.guest);
  if (cs.host < 0) c.fail(o.at("host"), "unknown body \"" + p.host + "\"");
  if (cs.guest < 0) c.fail(o.at("guest"), "unknown body \"" + p.guest + "\"");
  if (p.host == p.guest) c.fail(o.at("guest"), "host and guest must be different bodies");
  std::vector<std::pair<DetectorKind, const char*>> detectors;
  for (const DetectorName& d : detector_names()) detectors.emplace_back(d.kind, d.name);
  cs.detector = pick(o, "detector", "voxel", detectors);
  const json* vs = o.get("voxel_size");
  if (!vs || (vs->is_string() && vs->get<std::string>() == "auto")) {
    cs.voxel_size = 0.0;
    o.out()["voxel_size"] = "auto";
  } else {
    cs.voxel_size = o.number("voxel_size", std::nullopt, 0.0, 1e6, true);
  }
  const json* cz = o.get("cell_size");
  if (!cz || (cz->is_string() && cz->get<std::string>() == "auto")) {
    cs.cell_size = 0.0;
    o.out()["cell_size"] = "auto";
  } else {
    cs.cell_size = o.number("cell_size", std::nullopt, 0.0, 1e6, true);
  }
  cs.region = pick<Region>(o, "region", "half", {{Region::half, "half"}, {Region::full, "full"}, {Region::overlap, "overlap"}});
  cs.margin = static_cast<int>(o.integer("margin", 1, 0, 64));
  cs.host_nodes = pick<HostNodes>(o, "host_nodes", "all", {{HostNodes::all, "all"}, {HostNodes::surface, "surface"}});
  cs.eliminator = pick(o, "eliminator", "line", eliminator_names());
  cs.orient = pick<Orient>(o, "orient", "paper", {{Orient::paper, "paper"}, {Orient::guest, "guest"}, {Orient::outward, "outward"}});
  cs.two_sided = o.boolean("two_sided", false);
  cs.invert_push = o.boolean("invert_push", false);
  cs.separation_time = o.number("separation_time", Collision::kSeparationTime, 0.0, 1e6, true);
  const json* f = o.get("force");
  if (!f || (f->is_string() && f->get<std::string>() == "auto")) {
    cs.force_rule = ForceRule::automatic;
    o.out()["force"] = "auto";
  } else if (f->is_object()) {
    Obj fo(c, *f, o.at("force"), o.out()["force"]);
    cs.force_rule = ForceRule::penalty;
    cs.stiffness = fo.number("stiffness", std::nullopt, 0.0, 1e12);
    fo.finish();
  } else if (f->is_string()) {
    c.fail(o.at("force"), "expected a number of newtons, \"auto\" or {\"stiffness\": N/m}");
  } else {
    cs.force_rule = ForceRule::constant;
    cs.force = o.number("force", std::nullopt, 0.0, 1e12);
  }
  o.finish();
  return p;
}

void read_contacts(const Ctx& c, Obj& top, Scene& s) {
  s.resolved["contacts"] = json::array();
  const json* cs = top.get("contacts");
  if (!cs) return;
  as_list(c, "contacts", *cs);
  for (std::size_t i = 0; i < cs->size(); ++i) {
    json r;
    s.contacts.push_back(read_contact(c, (*cs)[i], join("contacts", i), r, s));
    s.resolved["contacts"].push_back(r);
  }
}

void read_references(const Ctx& c, Obj& top, Scene& s) {
  static const json empty = json::object();
  const json* rj = top.get("references");
  Obj o(c, rj ? *rj : empty, "references", s.resolved["references"]);
  o.out()["solvers"] = json::array();
  if (const json* sv = o.get("solvers")) {
    as_list(c, o.at("solvers"), *sv);
    for (std::size_t i = 0; i < sv->size(); ++i) {
      const std::string n = as_string(c, join(o.at("solvers"), i), (*sv)[i]);
      bool* flag = n == "cgal" ? &s.references.cgal : n == "fcl" ? &s.references.fcl : n == "ccd" ? &s.references.ccd : nullptr;
      if (!flag) c.fail(join(o.at("solvers"), i), "unknown solver \"" + n + "\" (expected \"cgal\", \"fcl\" or \"ccd\")");
      if (*flag) c.fail(join(o.at("solvers"), i), "solver \"" + n + "\" listed twice");
      *flag = true;
      o.out()["solvers"].push_back(n);
    }
  }
  s.references.every = static_cast<int>(o.integer("every", 1, 1, 2000000000));
  s.references.volume = o.boolean("volume", false);
  o.finish();
}

void read_output(const Ctx& c, Obj& top, Scene& s) {
  static const json empty = json::object();
  const json* oj = top.get("output");
  Obj o(c, oj ? *oj : empty, "output", s.resolved["output"]);
  s.frames_every = static_cast<int>(o.integer("frames_every", 0, 0, 2000000000));
  s.trajectory = o.boolean("trajectory", false);
  const std::string fmt = o.choice("format", std::string("vtp"), {"vtp", "vtu", "vtk"});
  s.frame_format = fmt == "vtu" ? FrameFormat::vtu : fmt == "vtk" ? FrameFormat::vtk : FrameFormat::vtp;
  o.finish();
}

}  // namespace

Scene scene_from_json(const json& doc, const std::string& file, const std::string& dir) {
  Ctx c{file};
  Scene s;
  s.file = file;
  s.dir = dir;
  Obj top(c, doc, "", s.resolved);
  s.name = top.string("name", std::filesystem::path(file).stem().string());
  if (const json* seed = top.get("seed")) {
    s.seed = as_integer(c, "seed", *seed);
    s.resolved["seed"] = *s.seed;
  }
  read_time(c, top, s);
  read_effects(c, top, s);
  s.gravity = top.vec3("gravity", Vec3(0.0, 0.0, -9.81));
  read_bodies(c, top, s, dir);
  read_contacts(c, top, s);
  read_references(c, top, s);
  read_output(c, top, s);
  top.finish();
  return s;
}

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

Scene parse_scene(const std::string& text, const std::string& file,
                  const std::vector<std::pair<std::string, std::string>>& overrides) {
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
  for (const auto& [k, v] : overrides) apply_override(doc, k, v);
  std::string dir = std::filesystem::path(file).parent_path().string();
  if (dir.empty()) dir = ".";
  return scene_from_json(doc, file, dir);
}

Scene rescale_dt(const Scene& scene, int factor) {
  if (factor < 1) throw InputError(scene.file + ": time.dt", "the dt divisor must be >= 1");
  json s = scene.resolved;
  auto scale = [factor](json& v) {
    if (v.is_number_integer() && v.get<long long>() > 0) v = v.get<long long>() * factor;
  };
  s["time"]["dt"] = scene.dt / factor;
  scale(s["time"]["steps"]);
  scale(s["time"]["window"]);
  if (s["time"].contains("settle")) scale(s["time"]["settle"]["max_steps"]);
  for (json& b : s["bodies"]) {
    if (b.contains("pressure")) scale(b["pressure"]["ramp_steps"]);
    for (json& l : b["loads"]) scale(l["ramp_steps"]);
    for (json& d : b["drivers"]) {
      if (d["from_step"].get<long long>() > 0) d["from_step"] = (d["from_step"].get<long long>() - 1) * factor + 1;
      scale(d["to_step"]);
    }
  }
  scale(s["references"]["every"]);
  scale(s["output"]["frames_every"]);
  return scene_from_json(s, scene.file, scene.dir);
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

Scene load_scene(const std::string& path,
                 const std::vector<std::pair<std::string, std::string>>& overrides) {
  return parse_scene(read_text_file(path), path, overrides);
}

}  // namespace harness
