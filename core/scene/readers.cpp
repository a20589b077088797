// The section readers: a validated JSON document into a Scene, one function per section (time,
// effects, bodies and what they hold, contacts, references, output). Each key's type, range,
// default and names come from the key table (keys.hpp) through the accessors of check.hpp; here
// are the scene's fields they fill and the checks across keys (docs/scenes.md, "What the schema
// cannot express").
#include "core/scene/scene.hpp"

#include "core/collision/responses/force_rule.hpp"
#include "core/limits.hpp"
#include "core/scene/check.hpp"

#include <filesystem>
#include <set>

namespace harness {

using nlohmann::json;
using namespace scene_check;

std::vector<std::pair<EffectFlag, const char*>> effect_names() {
  return {{kSprings, "springs"}, {kBulk, "bulk"}, {kDamping, "damping"}, {kGravity, "gravity"}, {kPins, "pins"},
          {kDrivers, "drivers"}, {kPressure, "pressure"}, {kLoads, "loads"}, {kContact, "contact"}};
}

const char* effect_name(EffectFlag e) {
  for (const auto& [flag, name] : effect_names())
    if (flag == e) return name;
  return "?";
}

namespace {

Selection read_selection(const Ctx& c, const json& j, const std::string& path, json& out) {
  Obj o(c, j, path, out, "selection");
  Selection s;
  s.path = path;
  int n = 0;
  std::string names;
  for (const SceneKey& k : scene_keys())
    if (std::string(k.kind) == "selection") {
      n += o.has(k.name) ? 1 : 0;
      names += (names.empty() ? "\"" : ", \"") + std::string(k.name) + "\"";
    }
  if (n != 1) c.fail(path, "a selection needs exactly one of " + names);
  if (o.has("side")) {
    const int side = static_cast<int>(o.word<Side>("side"));  // -x, +x, -y, +y, -z, +z
    s.kind = Selection::side;
    s.sign = side % 2 == 0 ? -1 : 1;
    s.axis = side / 2;
  } else if (o.has("box")) {
    s.kind = Selection::box;
    Obj b(c, *o.get("box"), o.at("box"), o.out()["box"], "selection.box");
    s.min = b.vec3("min");
    s.max = b.vec3("max");
    b.finish();
    if ((s.min.array() > s.max.array()).any()) c.fail(o.at("box"), "min exceeds max");
  } else {
    s.kind = Selection::all;
    if (!o.boolean("all")) c.fail(o.at("all"), "\"all\" must be true");
  }
  o.finish();
  return s;
}

ShapeSpec read_shape(const Ctx& c, const json& j, const std::string& path, json& out, const std::string& dir) {
  ShapeSpec s;
  {
    Obj t(c, j, path, out, "shape");
    s.type = t.word<ShapeType>("type");
  }
  // The keys of the variant `type` names (shape.box, shape.sphere, ...).
  const std::string kind = std::string("shape.") + scene_word(s.type);
  Obj o(c, j, path, out, scene_kind(kind).name);
  o.get("type");
  auto fill = [&]() { s.volume_fill = o.word<FillWord>("fill") == FillWord::volume; };
  if (s.type == ShapeType::box) {
    s.min = o.vec3("min");
    s.max = o.vec3("max");
    if (!(s.min.array() < s.max.array()).all()) c.fail(o.at("max"), "max must exceed min on every axis");
    const json* cells = o.get("cells");
    if (!cells) c.fail(o.at("cells"), "missing required key");
    if (!cells->is_array() || cells->size() != 3) c.fail(o.at("cells"), "expected a list of 3 integers");
    const SceneKey& ck = o.row("cells");
    const long long lo = static_cast<long long>(ck.lo), hi = static_cast<long long>(ck.hi);
    long long total = 1;
    for (int a = 0; a < 3; ++a) {
      const long long n = as_integer(c, join(o.at("cells"), a), (*cells)[a]);
      if (n < lo || n > hi)
        c.fail(join(o.at("cells"), a), "value out of range (" + std::to_string(lo) + " to " + std::to_string(hi) + ")");
      s.cells[a] = static_cast<int>(n);
      total *= (n + 1);
    }
    if (total > kMaxBoxNodes) c.fail(o.at("cells"), "too many nodes (" + std::to_string(total) + " > " + std::to_string(kMaxBoxNodes) + ")");
    o.out()["cells"] = {s.cells[0], s.cells[1], s.cells[2]};
    s.alternating_diagonals = o.word_in("diagonals", {"aligned", "alternating"}) == "alternating";
    // A box lattice is always volumetric: of the fills a surface takes (the shared fill key), only
    // volume.
    if (o.has("fill") && o.word_in("fill", word_list<FillWord>()) != scene_word(FillWord::volume))
      c.fail(o.at("fill"), "a box lattice is always volumetric");
    s.volume_fill = true;
    o.out()["fill"] = o.row("fill").def;
  } else if (s.type == ShapeType::sphere || s.type == ShapeType::ellipsoid) {
    s.center = o.vec3("center");
    if (s.type == ShapeType::sphere) {
      s.radius = o.number("radius");
      s.radii = Vec3::Constant(s.radius);
    } else {
      s.radii = o.vec3("radii");
    }
    s.subdivisions = static_cast<int>(o.integer("subdivisions"));
    fill();
  } else if (s.type == ShapeType::cylinder) {
    s.center = o.vec3("center");
    s.axis = o.vec3("axis");
    if (s.axis.norm() < 1e-12) c.fail(o.at("axis"), "axis must be non-zero");
    s.radius = o.number("radius");
    s.length = o.number("length");
    s.segments = static_cast<int>(o.integer("segments"));
    s.rings = static_cast<int>(o.integer("rings"));
    if (static_cast<long long>(s.segments) * (s.rings + 1) > kMaxCylinderNodes)
      c.fail(o.at("rings"), "too many nodes (segments * (rings + 1) > " + std::to_string(kMaxCylinderNodes) + ")");
    fill();
  } else {
    const std::string p = o.string("path");
    std::filesystem::path fp(p);
    s.path = fp.is_absolute() ? p : (std::filesystem::path(dir) / fp).lexically_normal().string();
    s.scale = o.number("scale");
    s.translate = o.vec3("translate");
    fill();
  }
  o.finish();
  return s;
}

Material read_material(const Ctx& c, const json* j, const std::string& path, json& out, bool shell, bool box) {
  static const json empty = json::object();
  Obj o(c, j ? *j : empty, path, out, "material");
  Material m;
  m.density = o.number("density");
  if (o.has("stiffness") && o.has("youngs_modulus"))
    c.fail(path, "both \"stiffness\" (N/m per spring) and \"youngs_modulus\" (Pa) are given: choose one");
  if (o.has("youngs_modulus")) {
    m.youngs_modulus = o.number("youngs_modulus");
    if (shell) m.thickness = o.number("thickness");
  } else {
    m.stiffness = o.number("stiffness");
  }
  if (o.has("thickness") && !(shell && m.youngs_modulus > 0.0))
    c.fail(o.at("thickness"), shell ? "a thickness goes with \"youngs_modulus\"" : "only a shell (fill \"shell\") has a thickness");
  m.law = o.word<SpringLawKind>("law");
  m.nonlinearity = o.number("nonlinearity");
  m.damping = o.number("damping");
  m.mass_damping = o.number("mass_damping");
  m.bulk_modulus = o.number("bulk_modulus");
  if (m.bulk_modulus > 0.0 && !box)
    c.fail(o.at("bulk_modulus"), "only a box lattice (shape \"box\") has the cells the bulk effect acts on");
  o.finish();
  return m;
}

// A list of objects of one kind under `key` of `o` (pins, drivers, loads, bodies, contacts): each
// element read by `read`, its resolved value appended to the resolved list.
template <class Read>
void read_list(Obj& o, const std::string& key, Read&& read) {
  o.out()[key] = json::array();
  const json* list = o.get(key);
  if (!list) return;
  as_list(o.ctx(), o.at(key), *list);
  for (std::size_t i = 0; i < list->size(); ++i) {
    json r;
    read((*list)[i], join(o.at(key), i), r);
    o.out()[key].push_back(r);
  }
}

// A driver's or a load's selection: under `select`, resolved in place.
Selection read_select(Obj& o) {
  json sel;
  Selection s = read_selection(o.ctx(), o.require("select"), o.at("select"), sel);
  o.out()["select"] = sel;
  return s;
}

BodySpec read_body(const Ctx& c, const json& j, const std::string& path, json& out, const std::string& dir) {
  Obj o(c, j, path, out, "body");
  BodySpec b;
  b.path = path;
  b.name = o.string("name");
  b.shape = read_shape(c, o.require("shape"), o.at("shape"), o.out()["shape"], dir);
  b.material = read_material(c, o.get("material"), o.at("material"), o.out()["material"], !b.shape.volume_fill,
                             b.shape.type == ShapeType::box);
  b.velocity = o.vec3("velocity");
  read_list(o, "pins", [&](const json& e, const std::string& at, json& r) { b.pins.push_back(read_selection(c, e, at, r)); });
  read_list(o, "drivers", [&](const json& e, const std::string& at, json& r) {
    Obj d(c, e, at, r, "driver");
    DriverSpec ds;
    ds.select = read_select(d);
    ds.velocity = d.vec3("velocity");
    ds.from_step = static_cast<int>(d.integer("from_step"));
    ds.to_step = static_cast<int>(d.integer("to_step"));
    if (ds.to_step >= 0 && ds.to_step < ds.from_step) c.fail(d.at("to_step"), "to_step is before from_step");
    d.finish();
    b.drivers.push_back(ds);
  });
  read_list(o, "loads", [&](const json& e, const std::string& at, json& r) {
    Obj l(c, e, at, r, "load");
    LoadSpec ls;
    ls.select = read_select(l);
    ls.force = l.vec3("force");
    ls.ramp_steps = static_cast<int>(l.integer("ramp_steps"));
    l.finish();
    b.loads.push_back(ls);
  });
  if (const json* p = o.get("pressure")) {
    Obj po(c, *p, o.at("pressure"), o.out()["pressure"], "pressure");
    b.pressure.present = true;
    b.pressure.from = po.number("from");
    b.pressure.to = po.number("to");
    b.pressure.ramp_steps = static_cast<int>(po.integer("ramp_steps"));
    po.finish();
  }
  o.finish();
  return b;
}

void read_time(const Ctx& c, Obj& top, Scene& s) {
  Obj t(c, top.require("time"), "time", s.resolved["time"], "time");
  s.dt = t.number("dt");
  s.steps = static_cast<int>(t.integer("steps"));
  s.integrator = t.word<Integrator>("integrator");
  s.guard = t.word<Guard>("guard");
  s.cg_tolerance = t.number("cg_tolerance");
  s.max_substeps = static_cast<int>(t.integer("max_substeps"));
  s.window = static_cast<int>(t.integer("window"));
  if (const json* st = t.get("settle"); st && !st->is_null()) {  // null: no settling (--steps)
    Obj o(c, *st, t.at("settle"), t.out()["settle"], "settle");
    s.settle.present = true;
    s.settle.tolerance = o.number("tolerance");
    s.settle.max_steps = static_cast<int>(o.integer("max_steps"));
    o.finish();
  }
  t.finish();
}

// A list of distinct words of a key's names: the effects, the reference solvers.
std::vector<std::string> read_words(const Ctx& c, const std::string& path, const json& list, const SceneKey& k,
                                    const std::string& noun, const std::string& expected) {
  as_list(c, path, list);
  std::vector<std::string> out;
  for (std::size_t i = 0; i < list.size(); ++i) {
    const std::string w = as_string(c, join(path, i), list[i]);
    bool known = false;
    for (const std::string& n : k.names) known = known || n == w;
    if (!known) c.fail(join(path, i), "unknown " + noun + " \"" + w + "\" (expected " + expected + ")");
    for (const std::string& seen : out)
      if (seen == w) c.fail(join(path, i), noun + " \"" + w + "\" listed twice");
    out.push_back(w);
  }
  return out;
}

void read_effects(const Ctx& c, Obj& top, Scene& s) {
  json& R = s.resolved;
  R["effects"] = json::array();
  const SceneKey& k = top.row("effects");
  if (const json* eff = top.get("effects")) {
    std::string expected = "one of ";
    for (std::size_t i = 0; i < k.names.size(); ++i) expected += (i ? ", " : "") + k.names[i];
    for (const std::string& e : read_words(c, "effects", *eff, k, "effect", expected))
      for (const auto& [bit, name] : effect_names())
        if (e == name) s.effects |= bit;
  }
  for (const auto& [b, n] : effect_names())
    if (s.effects & b) R["effects"].push_back(n);
}

void read_bodies(const Ctx& c, Obj& top, Scene& s, const std::string& dir) {
  const json& bodies = as_list(c, "bodies", top.require("bodies"));
  if (bodies.size() < static_cast<std::size_t>(top.row("bodies").lo)) c.fail("bodies", "at least one body is needed");
  std::set<std::string> names;
  read_list(top, "bodies", [&](const json& e, const std::string& at, json& r) {
    BodySpec b = read_body(c, e, at, r, dir);
    if (!names.insert(b.name).second) c.fail(join(at, "name"), "duplicate body name \"" + b.name + "\"");
    s.bodies.push_back(std::move(b));
  });
}

// contacts.N.force: the rule of the registry (core/collision/responses/force_rule.hpp) a number,
// a word or an object names, and its parameters from that rule's rows (kind force.RULE).
void read_force(const Ctx& c, Obj& o, ContactSpec& cs) {
  const SceneKey& fk = o.row("force");
  const json* given = o.get("force");
  const json& f = given ? *given : fk.def;
  const std::string at = o.at("force");
  std::string words;
  for (const ForceRuleDef& r : force_rules())
    if (r.form == RuleForm::word) words += std::string(words.empty() ? "" : ", ") + "\"" + r.name + "\"";
  auto wrong = [&] {
    c.fail(at, "expected a number of newtons, " + words + " or an object {\"rule\": NAME, ...} (docs/scenes.md, \"Force rules\")");
  };
  if (f.is_string()) {
    const ForceRuleDef* r = rule_of_form(RuleForm::word, f.get<std::string>());
    if (!r) wrong();
    cs.force_rule = r->name;
    cs.force_parameters.clear();
    o.out()["force"] = r->name;
  } else if (f.is_number()) {
    const ForceRuleDef* r = rule_of_form(RuleForm::number);
    if (!r) wrong();
    const RuleParameter& p = r->parameters[0];
    const double x = as_number(c, at, f);
    if (x < p.lo || x > p.hi) c.fail(at, "value " + fmt(x) + " out of range (>= " + fmt(p.lo) + ", <= " + fmt(p.hi) + ")");
    cs.force_rule = r->name;
    cs.force_parameters = {x};
    o.out()["force"] = x;
  } else if (f.is_object()) {
    std::string name = kDefaultObjectRule;
    std::string objects;
    for (const ForceRuleDef& r : force_rules())
      if (r.form == RuleForm::object) objects += std::string(objects.empty() ? "" : ", ") + r.name;
    if (const auto it = f.find("rule"); it != f.end()) name = as_string(c, join(at, "rule"), *it);
    const ForceRuleDef* r = find_force_rule(name);
    if (!r || r->form != RuleForm::object) c.fail(join(at, "rule"), "unknown rule \"" + name + "\" (one of " + objects + ")");
    std::string takes;
    for (const RuleParameter& p : r->parameters) takes += std::string(takes.empty() ? "" : ", ") + p.name;
    for (const auto& [key, value] : f.items()) {
      bool known = key == "rule";
      for (const RuleParameter& p : r->parameters) known = known || key == p.name;
      if (!known) c.fail(join(at, key), "unknown key (rule " + name + " takes " + (takes.empty() ? "none" : takes) + ")");
    }
    Obj fo(c, f, at, o.out()["force"], scene_kind(std::string("force.") + r->name).name);
    fo.get("rule");
    if (f.contains("rule")) fo.out()["rule"] = name;
    cs.force_rule = r->name;
    cs.force_parameters.clear();
    for (const RuleParameter& p : r->parameters) cs.force_parameters.push_back(fo.number(p.name));
    fo.finish();
  } else {
    wrong();
  }
}

// A pair's parameters (every key of a contact but host, guest and label), each from its row of
// the key table: its value, or its default when absent. Marks the spec made from the table.
void read_contact_spec(const Ctx& c, Obj& o, ContactSpec& cs) {
  cs.detector = o.word("detector");
  cs.voxel_size = o.length_or_auto("voxel_size");
  cs.cell_size = o.length_or_auto("cell_size");
  cs.volume_pixel = o.length_or_auto("volume_pixel");
  cs.region = o.word<Region>("region");
  cs.margin = static_cast<int>(o.integer("margin"));
  cs.host_nodes = o.word<HostNodes>("host_nodes");
  cs.eliminator = o.word("eliminator");
  cs.orient = o.word<Orient>("orient");
  cs.two_sided = o.boolean("two_sided");
  cs.invert_push = o.boolean("invert_push");
  cs.separation_time = o.number("separation_time");
  cs.damping = o.number("damping");
  cs.field_resample = o.number("field_resample");
  read_force(c, o, cs);
  cs.made = kContactSpecMade;
}

// contacts.N.response ("plugin:PATH", PATH against the scene's directory) and its parameters.
void read_response(const Ctx& c, Obj& o, ContactPairSpec& p, const std::string& dir) {
  const json* r = o.get("response");
  const json* params = o.get("response_parameters");
  if (params && !r) c.fail(o.at("response_parameters"), "only with response");
  if (!r) return;
  const std::string v = as_string(c, o.at("response"), *r);
  const std::string prefix = "plugin:";
  if (v.rfind(prefix, 0) != 0 || v.size() == prefix.size())
    c.fail(o.at("response"), "expected \"plugin:PATH\" (a shared library: docs/plugins.md), got \"" + v + "\"");
  const std::filesystem::path fp(v.substr(prefix.size()));
  p.plugin = fp.is_absolute() ? fp.string() : (std::filesystem::path(dir) / fp).lexically_normal().string();
  o.out()["response"] = v;
  if (!params) return;
  if (!params->is_object()) c.fail(o.at("response_parameters"), "expected an object of named numbers, got " + type_name(*params));
  for (auto it = params->begin(); it != params->end(); ++it) {
    if (it.key().empty()) c.fail(o.at("response_parameters"), "an empty parameter name");
    p.plugin_parameters.emplace_back(it.key(), as_number(c, join(o.at("response_parameters"), it.key()), it.value()));
  }
  o.out()["response_parameters"] = *params;
}

ContactPairSpec read_contact(const Ctx& c, const json& j, const std::string& path, json& r, const Scene& s) {
  Obj o(c, j, path, r, "contact");
  ContactPairSpec p;
  p.path = path;
  p.host = o.string("host");
  p.guest = o.string("guest");
  p.label = o.string("label", p.host + "/" + p.guest);
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
  read_contact_spec(c, o, cs);
  read_response(c, o, p, s.dir);
  o.finish();
  return p;
}

void read_contacts(const Ctx& c, Obj& top, Scene& s) {
  read_list(top, "contacts", [&](const json& e, const std::string& at, json& r) {
    s.contacts.push_back(read_contact(c, e, at, r, s));
  });
}

// The references section into `r`, every key from its row of the table.
void read_reference_spec(const Ctx& c, Obj& o, ReferenceSpec& r) {
  o.out()["solvers"] = json::array();
  if (const json* sv = o.get("solvers")) {
    const SceneKey& k = o.row("solvers");
    std::string expected;
    for (std::size_t i = 0; i < k.names.size(); ++i)
      expected += std::string(i == 0 ? "" : i + 1 == k.names.size() ? " or " : ", ") + "\"" + k.names[i] + "\"";
    for (const std::string& n : read_words(c, o.at("solvers"), *sv, k, "solver", expected)) {
      const Solver v = word_value<Solver>(n);
      (v == Solver::cgal ? r.cgal : v == Solver::fcl ? r.fcl : r.ccd) = true;
      o.out()["solvers"].push_back(n);
    }
  }
  r.every = static_cast<int>(o.integer("every"));
  r.volume = o.boolean("volume");
}

void read_references(const Ctx& c, Obj& top, Scene& s) {
  static const json empty = json::object();
  const json* rj = top.get("references");
  Obj o(c, rj ? *rj : empty, "references", s.resolved["references"], "references");
  read_reference_spec(c, o, s.references);
  o.finish();
}

void read_output(const Ctx& c, Obj& top, Scene& s) {
  static const json empty = json::object();
  const json* oj = top.get("output");
  Obj o(c, oj ? *oj : empty, "output", s.resolved["output"], "output");
  s.frames_every = static_cast<int>(o.integer("frames_every"));
  s.trajectory = o.boolean("trajectory");
  s.frame_format = o.word<FrameFormat>("format");
  o.finish();
}

}  // namespace

Scene scene_from_json(const json& doc, const std::string& file, const std::string& dir) {
  Ctx c{file};
  Scene s;
  s.file = file;
  s.dir = dir;
  Obj top(c, doc, "", s.resolved, "scene");
  s.name = top.string("name", std::filesystem::path(file).stem().string());
  if (const json* seed = top.get("seed")) {
    s.seed = as_integer(c, "seed", *seed);
    s.resolved["seed"] = *s.seed;
  }
  read_time(c, top, s);
  read_effects(c, top, s);
  s.gravity = top.vec3("gravity");
  read_bodies(c, top, s, dir);
  read_contacts(c, top, s);
  read_references(c, top, s);
  read_output(c, top, s);
  top.finish();
  return s;
}

Material material_defaults() {
  const Ctx c{"(the key table's defaults)"};
  json resolved = json::object();
  return read_material(c, nullptr, "material", resolved, false, true);
}

ReferenceSpec reference_spec_defaults() {
  const Ctx c{"(the key table's defaults)"};
  const json empty = json::object();
  json resolved = json::object();
  Obj o(c, empty, "references", resolved, "references");
  ReferenceSpec r;
  read_reference_spec(c, o, r);
  o.finish();
  return r;
}

ContactSpec contact_spec_defaults() {
  const Ctx c{"(the key table's defaults)"};
  const json empty = json::object();
  json resolved = json::object();
  Obj o(c, empty, "contact", resolved, "contact");
  ContactSpec cs{};
  read_contact_spec(c, o, cs);
  o.finish();
  return cs;
}

}  // namespace harness
