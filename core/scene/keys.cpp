// The scene format's key table (keys.hpp says what reads it). One row per key, in the order the
// loader reads them within their kind; the descriptions are the schema's.
#include "core/scene/keys.hpp"

#include "core/collision/responses/collision_eliminator.hpp"
#include "core/collision/responses/force_rule.hpp"
#include "core/limits.hpp"
#include "core/scene/scene.hpp"

#include <cctype>
#include <cmath>
#include <cstdio>
#include <deque>
#include <stdexcept>

namespace harness {

using nlohmann::json;

// ---- the scene's words for enumerations -----------------------------------------------------

template <>
const std::vector<std::pair<Integrator, const char*>>& scene_words<Integrator>() {
  static const std::vector<std::pair<Integrator, const char*>> w = {{Integrator::symplectic_euler, "symplectic_euler"},
                                                                    {Integrator::implicit_euler, "implicit_euler"}};
  return w;
}
template <>
const std::vector<std::pair<ShapeType, const char*>>& scene_words<ShapeType>() {
  static const std::vector<std::pair<ShapeType, const char*>> w = {
      {ShapeType::box, "box"}, {ShapeType::sphere, "sphere"}, {ShapeType::ellipsoid, "ellipsoid"},
      {ShapeType::cylinder, "cylinder"}, {ShapeType::mesh, "mesh"}};
  return w;
}
template <>
const std::vector<std::pair<FillWord, const char*>>& scene_words<FillWord>() {
  static const std::vector<std::pair<FillWord, const char*>> w = {{FillWord::shell, "shell"}, {FillWord::volume, "volume"}};
  return w;
}
template <>
const std::vector<std::pair<Solver, const char*>>& scene_words<Solver>() {
  static const std::vector<std::pair<Solver, const char*>> w = {
      {Solver::cgal, "cgal"}, {Solver::fcl, "fcl"}, {Solver::ccd, "ccd"}};
  return w;
}
template <>
const std::vector<std::pair<Side, const char*>>& scene_words<Side>() {
  static const std::vector<std::pair<Side, const char*>> w = {
      {Side::minus_x, "-x"}, {Side::plus_x, "+x"}, {Side::minus_y, "-y"},
      {Side::plus_y, "+y"}, {Side::minus_z, "-z"}, {Side::plus_z, "+z"}};
  return w;
}
template <>
const std::vector<std::pair<Guard, const char*>>& scene_words<Guard>() {
  static const std::vector<std::pair<Guard, const char*>> w = {{Guard::refuse, "refuse"}, {Guard::substep, "substep"}};
  return w;
}
template <>
const std::vector<std::pair<FrameFormat, const char*>>& scene_words<FrameFormat>() {
  static const std::vector<std::pair<FrameFormat, const char*>> w = {
      {FrameFormat::vtp, "vtp"}, {FrameFormat::vtu, "vtu"}, {FrameFormat::vtk, "vtk"}};
  return w;
}
template <>
const std::vector<std::pair<SpringLawKind, const char*>>& scene_words<SpringLawKind>() {
  static const std::vector<std::pair<SpringLawKind, const char*>> w = {
      {SpringLawKind::linear, "linear"}, {SpringLawKind::cubic, "cubic"}, {SpringLawKind::exponential, "exponential"}};
  return w;
}
template <>
const std::vector<std::pair<Region, const char*>>& scene_words<Region>() {
  static const std::vector<std::pair<Region, const char*>> w = {
      {Region::half, "half"}, {Region::full, "full"}, {Region::overlap, "overlap"}};
  return w;
}
template <>
const std::vector<std::pair<HostNodes, const char*>>& scene_words<HostNodes>() {
  static const std::vector<std::pair<HostNodes, const char*>> w = {{HostNodes::all, "all"}, {HostNodes::surface, "surface"}};
  return w;
}
template <>
const std::vector<std::pair<Orient, const char*>>& scene_words<Orient>() {
  static const std::vector<std::pair<Orient, const char*>> w = {
      {Orient::paper, "paper"}, {Orient::guest, "guest"}, {Orient::outward, "outward"}};
  return w;
}

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kMaxSteps = 2e9;  // every step count's upper bound

std::vector<std::string> effect_words() {
  std::vector<std::string> out;
  for (const auto& [flag, name] : effect_names()) out.emplace_back(name);
  return out;
}
// The detectors' registry (collision_detector.hpp): their names and what each does.
std::vector<std::string> detector_words() {
  std::vector<std::string> out;
  for (const DetectorDef& d : detectors()) out.emplace_back(d.name);
  return out;
}
std::string detector_doc() {
  std::string doc;
  for (const DetectorDef& d : detectors()) doc += std::string(doc.empty() ? "" : ", ") + d.name + " (" + d.doc + ")";
  return doc + "; the exact ones need the reference library.";
}
// The eliminators' registry (collision_eliminator.hpp): their names and what each does.
std::vector<std::string> eliminator_words() {
  std::vector<std::string> out;
  for (const EliminatorDef& e : eliminators()) out.emplace_back(e.name);
  return out;
}
std::string eliminator_doc() {
  std::string d;
  for (const EliminatorDef& e : eliminators()) d += std::string(d.empty() ? "" : ", ") + e.name + " (" + e.doc + ")";
  return d + ".";
}

SceneKey key(const char* kind, const char* name, KeyType type) {
  SceneKey k;
  k.kind = kind;
  k.name = name;
  k.type = type;
  return k;
}

// The keys every surface shape shares (sphere, ellipsoid, cylinder, mesh): declared once, under
// one $defs entry of the schema.
SceneKey center(const char* kind) {
  return key(kind, "center", KeyType::vec3).fallback({0.0, 0.0, 0.0}).with_unit("m").shared("center").described(
      "Centre, m.");
}
SceneKey subdivisions(const char* kind) {
  return key(kind, "subdivisions", KeyType::integer)
      .range(0, kMaxSubdivisions)
      .fallback(2)
      .shared("subdivisions")
      .described("Icosphere subdivisions.");
}
SceneKey fill(const char* kind) {
  return key(kind, "fill", KeyType::word)
      .in(word_list<FillWord>())
      .fallback(scene_word(FillWord::shell))
      .shared("fill")
      .described("shell: a surface with edge and bending springs; volume: the surface plus an inner lattice tied to it.");
}

}  // namespace

std::string default_text(const json& v) {
  if (v.is_string()) return v.get<std::string>();
  if (v.is_boolean()) return v.get<bool>() ? "true" : "false";
  if (v.is_number()) {
    char b[32];
    std::snprintf(b, sizeof b, "%.10g", v.get<double>());
    return b;
  }
  if (v.is_array()) {
    std::string s = "[";
    for (std::size_t i = 0; i < v.size(); ++i) s += (i ? ", " : "") + default_text(v[i]);
    return s + "]";
  }
  return v.dump();
}

namespace {

// A bound as the descriptions write it: shortest, powers of ten as "2e9".
std::string bound_text(double v) {
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  const double a = std::fabs(v);
  if (a >= 1e4) {
    const int e = static_cast<int>(std::floor(std::log10(a)));
    const double m = v / std::pow(10.0, e);
    if (std::fabs(m * 100.0 - std::round(m * 100.0)) < 1e-9) {
      char b[32];
      std::snprintf(b, sizeof b, "%ge%d", std::round(m * 100.0) / 100.0, e);
      return b;
    }
  }
  char b[32];
  std::snprintf(b, sizeof b, "%.10g", v);
  return b;
}

}  // namespace

std::string range_text(const SceneKey& k) {
  const bool lo = std::isfinite(k.lo), hi = std::isfinite(k.hi);
  std::string r;
  switch (k.type) {
    case KeyType::string:
      return lo && k.lo >= 1 ? "non-empty" : "";
    case KeyType::list:
      return lo && k.lo >= 1 ? "at least " + bound_text(k.lo) : "";
    case KeyType::number:
    case KeyType::integer:
    case KeyType::length_or_auto:
    case KeyType::force:
    case KeyType::vec3:
    case KeyType::int3:
      if (k.lo_open)
        r = "> " + bound_text(k.lo) + (hi ? ", <= " + bound_text(k.hi) : "");
      else if (lo && hi)
        r = bound_text(k.lo) + " to " + bound_text(k.hi);
      else if (lo)
        r = ">= " + bound_text(k.lo);
      else if (hi)
        r = "<= " + bound_text(k.hi);
      if (r.empty()) return r;
      if (k.type == KeyType::vec3 || k.type == KeyType::int3) return r + " each";
      if (k.type == KeyType::length_or_auto) return r + ", or \"auto\"";
      if (k.type == KeyType::force) return "a number " + r;
      return r;
    default:
      return "";
  }
}

std::string key_description(const SceneKey& k) {
  // The made tail: "Required; RANGE." / "RANGE. Default: X." from the row.
  std::string tail;
  const std::string range = range_text(k);
  if (k.presence == Presence::required && k.type != KeyType::always_true)
    tail = range.empty() ? "Required." : "Required; " + range + ".";
  else if (!range.empty())
    tail = static_cast<char>(std::toupper(static_cast<unsigned char>(range[0]))) + range.substr(1) + ".";
  if (k.presence == Presence::defaulted && k.type != KeyType::object)
    tail += (tail.empty() ? "" : " ") + std::string("Default: ") + default_text(k.def) + ".";
  if (tail.empty()) return k.doc;
  return k.doc.empty() ? tail : k.doc + " " + tail;
}

namespace {

// A string the table keeps for the program's life (rows and kinds hold const char*).
const char* kept(std::string s) {
  static std::deque<std::string> store;
  store.push_back(std::move(s));
  return store.back().c_str();
}

// contacts.N.force and the rows of each object rule (kind force.RULE), from the force rules'
// registry (core/collision/responses/force_rule.hpp): a rule's file is its only statement.
void append_force_keys(std::vector<SceneKey>& keys) {
  SceneKey force = key("contact", "force", KeyType::force).holding("force").fallback("auto");
  std::string number, words, objects;
  for (const ForceRuleDef& r : force_rules()) {
    if (r.form == RuleForm::number) {
      const RuleParameter& p = r.parameters[0];
      force.range(p.lo, p.hi).with_unit(p.unit);
      number = std::string("A number: ") + r.doc + ", " + p.unit + " (rule " + r.name + ")";
    } else if (r.form == RuleForm::word) {
      force.names.emplace_back(r.name);
      words += std::string("; \"") + r.name + "\": " + r.doc;
    } else {
      objects += std::string(objects.empty() ? "" : "; ") + r.name + (r.name == std::string(kDefaultObjectRule) ? " (the default)" : "") + ": " + r.doc;
    }
  }
  std::string doc = number + words;
  if (!objects.empty()) doc += "; an object {\"rule\": NAME, PARAMETER: value, ...}, NAME one of " + objects;
  keys.push_back(force.described(doc + "."));
  for (const ForceRuleDef& r : force_rules()) {
    if (r.form != RuleForm::object) continue;
    const char* kind = kept(std::string("force.") + r.name);
    SceneKey rule = key(kind, "rule", KeyType::word).in({r.name});
    if (r.name == std::string(kDefaultObjectRule)) rule.optional().described("The rule; absent: this one.");
    else rule.required().described("The rule.");
    keys.push_back(rule);
    for (const RuleParameter& p : r.parameters) {
      SceneKey k = key(kind, p.name, KeyType::number).range(p.lo, p.hi).with_unit(p.unit);
      if (std::isnan(p.fallback)) k.required();
      else k.fallback(p.fallback);
      keys.push_back(k.described(std::string(p.doc) + (*p.unit ? std::string(", ") + p.unit : std::string()) + "."));
    }
  }
}

}  // namespace

// The table itself: data, one row per key (the one function over 80 lines that is a table).
const std::vector<SceneKey>& scene_keys() {
  static const std::vector<SceneKey> table = [] {
  std::vector<SceneKey> keys = {
      key("scene", "name", KeyType::string).computed().described("The scene's name in outputs. Default: the file's stem."),
      key("scene", "seed", KeyType::integer).optional().schema({{"minimum", std::numeric_limits<long long>::min()}, {"maximum", std::numeric_limits<long long>::max()}}).described("Recorded in the outputs; nothing in a run is random. Default: none."),
      key("scene", "time", KeyType::object).holding("time").described("Time stepping."),
      key("scene", "effects", KeyType::words).in(effect_words()).fallback(json::array()).described("Exactly what is simulated; each at most once. A body's pins, drivers, loads and pressure act only when their effect is listed; contact pairs are measured either way but pushed apart only with contact."),
      key("scene", "gravity", KeyType::vec3).fallback({0.0, 0.0, -9.81}).with_unit("m/s^2").described("Gravitational acceleration, m/s^2; used only when the effect gravity is listed."),
      key("scene", "bodies", KeyType::list).holding("body").range(1, kInf).described("The soft bodies; names unique."),
      key("scene", "contacts", KeyType::list).holding("contact").fallback(json::array()).described("Contact pairs."),
      key("scene", "references", KeyType::object).holding("references").fallback(json::object()).described("Exact measurement beside the run. Default: no solvers."),
      key("scene", "output", KeyType::object).holding("output").fallback(json::object()).described("What is written besides steps.csv and summary.json. Default: no frames."),
      key("time", "dt", KeyType::number).above(0.0, 1e3).with_unit("s").described("Time step, s."),
      key("time", "steps", KeyType::integer).range(0, kMaxSteps).counts(StepCount::count).described("Steps to run (with settle: at least this many)."),
      key("time", "integrator", KeyType::word).in(word_list<Integrator>()).fallback("symplectic_euler").described("symplectic_euler, or implicit_euler (linearised backward Euler, conjugate gradient)."),
      key("time", "guard", KeyType::word).in(word_list<Guard>()).fallback("refuse").described("When dt exceeds 0.9 dt_crit (Gershgorin bound on the tangent stiffness): refuse stops at load, substep splits the steps."),
      key("time", "max_substeps", KeyType::integer).range(1, 1000000).fallback(1000).described("Guard \"substep\": the most substeps a step may take; a step that needs more fails (exit 3, a blow-up or a contact far stiffer than the bodies), one at load is refused."),
      key("time", "cg_tolerance", KeyType::number).above(0.0, 0.1).fallback(1e-6).described("implicit_euler: the conjugate gradient's relative residual, |b - A dv| / |b| (docs/findings.md: the error it causes)."),
      key("time", "window", KeyType::integer).range(1, kMaxSteps).fallback(1000).counts(StepCount::count).by_steps_ref().described("Steps of the final window a run is judged over (its error figures as mean, maximum and chatter amplitude; the nodes' motion, the contact's input per time scale and growth; the stability class), never starting before every moving driver, load ramp and pressure ramp has finished."),
      key("time", "settle", KeyType::object).holding("settle").optional().null_ok().described("Equilibrium: after `steps`, go on until the relative force residual stays at most `tolerance` for 100 steps in a row, or `max_steps` more steps have run. null (or --steps N on the command line): run exactly `steps`. Default: none."),
      key("settle", "tolerance", KeyType::number).above(0.0, 1.0).fallback(1e-3).described("Relative force residual (dimensionless)."),
      key("settle", "max_steps", KeyType::integer).range(1, kMaxSteps).counts(StepCount::count).by_steps_ref().described("Steps at most after `steps`."),
      key("references", "solvers", KeyType::words).in(word_list<Solver>()).fallback(json::array()).described("Any of cgal (inside tests, signed distance of every surface vertex), fcl (triangle pairs, depth), ccd (libccd distance); each at most once."),
      key("references", "every", KeyType::integer).range(1, kMaxSteps).fallback(1).counts(StepCount::count).by_steps_ref().described("Measure every N steps (and the last)."),
      key("references", "volume", KeyType::boolean).fallback(false).described("CGAL's intersection volume (slow)."),
      key("output", "frames_every", KeyType::integer).range(0, kMaxSteps).fallback(0).counts(StepCount::count).by_steps_ref().described("Surface frames every N steps (plus step 0 and the last); 0 = none."),
      key("output", "trajectory", KeyType::boolean).fallback(false).described("trajectory.bin: every surface vertex at every measured step."),
      key("output", "format", KeyType::word).in(word_list<FrameFormat>()).fallback("vtp").described("Frames as VTK XML PolyData (vtp, with a ParaView collection per body), XML UnstructuredGrid (vtu, with a collection) or legacy ASCII (vtk)."),
      key("body", "name", KeyType::string).range(1, kInf).described("Unique among the bodies."),
      key("body", "shape", KeyType::object).holding("shape").described(""),
      key("body", "material", KeyType::object).holding("material").fallback(json::object()).described(""),
      key("body", "velocity", KeyType::vec3).fallback({0.0, 0.0, 0.0}).with_unit("m/s").described("Initial velocity of every node, m/s."),
      key("body", "pins", KeyType::list).holding("selection").fallback(json::array()).described("Selections held fixed (effect pins)."),
      key("body", "drivers", KeyType::list).holding("driver").fallback(json::array()).described("Kinematic drivers (effect drivers)."),
      key("body", "loads", KeyType::list).holding("load").fallback(json::array()).described("Applied forces (effect loads)."),
      key("body", "pressure", KeyType::object).holding("pressure").optional().described("Internal pressure (effect pressure). Default: none."),
      key("shape", "type", KeyType::word).in(word_list<ShapeType>()).described("box (a volumetric lattice), sphere, ellipsoid, cylinder or mesh (an OFF or OBJ file)."),
      key("shape.box", "min", KeyType::vec3).with_unit("m").described("Lower corner, m; below max on every axis."),
      key("shape.box", "max", KeyType::vec3).with_unit("m").described("Upper corner, m; above min on every axis."),
      key("shape.box", "cells", KeyType::int3).range(1, 1000).described("Cells along x, y, z; (nx+1)(ny+1)(nz+1) nodes at most " + bound_text(kMaxBoxNodes) + "."),
      key("shape.box", "diagonals", KeyType::word).in({"aligned", "alternating"}).fallback("aligned").described("How the surface's quads are split into triangles: \"aligned\", every quad along the same diagonal (a surface with a handedness: no mirror keeps it; each face keeps only the half turn about its own normal), or \"alternating\", the diagonal alternating from quad to quad like a checkerboard (mirror-symmetric about the box's mid-planes when the cells along the face are even in number). The springs are the same either way."),
      key("shape.box", "fill", KeyType::word).in({scene_word(FillWord::volume)}).fallback(scene_word(FillWord::volume)).described("A box lattice is always volumetric: only \"volume\" is accepted."),
      center("shape.sphere"),
      key("shape.sphere", "radius", KeyType::number).above(0.0).with_unit("m").described("Radius, m."),
      subdivisions("shape.sphere"),
      fill("shape.sphere"),
      center("shape.ellipsoid"),
      key("shape.ellipsoid", "radii", KeyType::vec3).above(0.0).with_unit("m").described("Semi-axes along x, y, z, m."),
      subdivisions("shape.ellipsoid"),
      fill("shape.ellipsoid"),
      center("shape.cylinder"),
      key("shape.cylinder", "axis", KeyType::vec3).fallback({0.0, 0.0, 1.0}).schema({{"not", {{"items", {{"const", 0}}}}}}).described("Axis direction (normalised by the loader); non-zero."),
      key("shape.cylinder", "radius", KeyType::number).above(0.0).with_unit("m").described("Radius, m."),
      key("shape.cylinder", "length", KeyType::number).above(0.0).with_unit("m").described("Length along the axis, m."),
      key("shape.cylinder", "segments", KeyType::integer).range(3, 100000).fallback(16).described("Nodes around a ring; segments * (rings + 1) at most " + bound_text(kMaxCylinderNodes) + "."),
      key("shape.cylinder", "rings", KeyType::integer).range(1, 100000).fallback(4).described("Rings along the axis."),
      fill("shape.cylinder"),
      key("shape.mesh", "path", KeyType::string).range(1, kInf).described("A closed triangle surface, OFF or OBJ; relative paths are relative to the scene file."),
      key("shape.mesh", "scale", KeyType::number).above(0.0).fallback(1.0).described("Factor on the file's coordinates."),
      key("shape.mesh", "translate", KeyType::vec3).fallback({0.0, 0.0, 0.0}).with_unit("m").described("Added after scaling, m."),
      fill("shape.mesh"),
      key("material", "density", KeyType::number).above(0.0).fallback(1000.0).with_unit("kg/m^3").described("kg/m^3; the body's mass is density times its enclosed volume."),
      key("material", "youngs_modulus", KeyType::number).above(0.0).optional().with_unit("Pa").described("Pa: spring stiffnesses derived from it. Not together with stiffness. Default: none."),
      key("material", "thickness", KeyType::number).above(0.0).optional().with_unit("m").described("Shell thickness, m; required with youngs_modulus on a shell (fill shell, not a box), accepted nowhere else."),
      key("material", "stiffness", KeyType::number).above(0.0).fallback(100.0).with_unit("N/m").described("N/m per spring, used when youngs_modulus is not given."),
      key("material", "law", KeyType::word).in(word_list<SpringLawKind>()).fallback("linear").described("The spring's force against strain."),
      key("material", "nonlinearity", KeyType::number).range(0.0, 1e6).fallback(0.0).described("The law's coefficient a (cubic: f = k eps l0 (1 + a eps^2); exponential: f = k l0 (e^(a eps) - 1)/a), dimensionless."),
      key("material", "damping", KeyType::number).range(0.0, kInf).fallback(0.0).with_unit("N s/m").described("Dashpot along each spring, N s/m."),
      key("material", "mass_damping", KeyType::number).range(0.0, kInf).fallback(0.0).with_unit("1/s").described("Global damping -alpha m v, alpha in 1/s."),
      key("material", "bulk_modulus", KeyType::number).range(0.0, kInf).fallback(0.0).with_unit("Pa").described("Pa: each box cell's resistance to a change of its volume, E = K V0 (J - 1)^2 / 2 with J = V / V0 (effect bulk; a box only). 0: none."),
      key("selection", "side", KeyType::word).in(word_list<Side>()).optional().described("A face of the rest bounding box."),
      key("selection", "box", KeyType::object).holding("selection.box").optional().described("Nodes whose rest position is inside (inclusive); min <= max on every axis."),
      key("selection", "all", KeyType::always_true).optional().described("Every node; must be true."),
      key("selection.box", "min", KeyType::vec3).with_unit("m").described("Lower corner, m."),
      key("selection.box", "max", KeyType::vec3).with_unit("m").described("Upper corner, m."),
      key("driver", "select", KeyType::object).holding("selection").described("The driven nodes."),
      key("driver", "velocity", KeyType::vec3).with_unit("m/s").described("m/s."),
      key("driver", "from_step", KeyType::integer).range(0, kMaxSteps).fallback(0).counts(StepCount::first_step).by_steps_ref().described("First driven step."),
      key("driver", "to_step", KeyType::integer).range(-1, kMaxSteps).fallback(-1).counts(StepCount::last_step).described("Last driven step; -1: to the end; not before from_step."),
      key("load", "select", KeyType::object).holding("selection").described("The loaded nodes."),
      key("load", "force", KeyType::vec3).with_unit("N").described("Total force, N."),
      key("load", "ramp_steps", KeyType::integer).range(0, kMaxSteps).fallback(0).counts(StepCount::count).by_steps_ref().described("Steps of the linear ramp from zero."),
      key("pressure", "from", KeyType::number).range(-1e9, 1e9).fallback(0.0).with_unit("Pa").described("Pa."),
      key("pressure", "to", KeyType::number).range(-1e9, 1e9).with_unit("Pa").described("Pa."),
      key("pressure", "ramp_steps", KeyType::integer).range(0, kMaxSteps).fallback(0).counts(StepCount::count).by_steps_ref().described("Steps of the ramp."),
      key("contact", "host", KeyType::string).described("A body's name."),
      key("contact", "guest", KeyType::string).described("Another body's name (not the host)."),
      key("contact", "label", KeyType::string).computed().range(1, kInf).described("The pair's name in the outputs (steps.csv pair, summary.json pairs[].pair, penetration_episodes.csv). Default: host/guest."),
      key("contact", "detector", KeyType::word).in(detector_words()).fallback("voxel").described(detector_doc()),
      key("contact", "voxel_size", KeyType::length_or_auto).above(0.0, 1e6).fallback("auto").with_unit("m").described("Voxel edge, m, rounded down to a power of two, or \"auto\" (the smallest power of two >= the host's mean surface edge at rest, its node spacing for a body without a surface; for voxel_exact doubled until it exceeds the host's longest surface edge / sqrt(3))."),
      key("contact", "cell_size", KeyType::length_or_auto).above(0.0, 1e6).fallback("auto").with_unit("m").described("Spatial hashing's cell, m, or \"auto\" (the host's mean surface edge at the current positions)."),
      key("contact", "volume_pixel", KeyType::length_or_auto).above(0.0, 1e6).fallback("auto").with_unit("m").described("The volume response's layered depth images' pixel edge, m, or \"auto\" (half the smaller of the two bodies' mean surface edges at rest)."),
      key("contact", "region", KeyType::word).in(word_list<Region>()).fallback("half").described("The voxel grid covers half the host's box, the full box, or their overlap."),
      key("contact", "margin", KeyType::integer).range(0, 64).fallback(1).described("Voxels added around the region."),
      key("contact", "host_nodes", KeyType::word).in(word_list<HostNodes>()).fallback("all").described("surface: only surface nodes enter the voxels (voxel_exact always lists the surface vertices)."),
      key("contact", "eliminator", KeyType::word).in(eliminator_words()).fallback("line").described(eliminator_doc()),
      key("contact", "orient", KeyType::word).in(word_list<Orient>()).fallback("paper").described("Which way line and plane push: paper (line from the nearest host node toward the guest node, plane agreeing with the host's outward normals), guest (both toward the guest node), outward (both agreeing with the host's outward normals)."),
      key("contact", "two_sided", KeyType::boolean).fallback(false).described("Also the other way round (the host's nodes against the guest's surface)."),
      key("contact", "invert_push", KeyType::boolean).fallback(false).described("Every push negated: a broken method, used by tests."),
      key("contact", "separation_time", KeyType::number).above(0.0, 1e6).fallback(0.1).with_unit("s").described("s, of force auto: separation speed = voxel size (detectors without a grid: the host's mean spring rest length) / separation_time."),
      key("contact", "field_resample", KeyType::number).above(0.0, 1.0).fallback(0.02).described("Detector distance_field: its field is sampled again when a host surface vertex has moved more than this share of a voxel since the last sampling (between samplings the field errs by at most that motion; a stale field pushes against where the host was, which feeds energy into a bounce)."),
      key("contact", "damping", KeyType::number).range(0.0, 1e9).fallback(0.0).with_unit("N s/m").described("A damping term on the contact force, a variant (not the paper's method): where a contact's force F is positive it becomes max(0, F - c v_n), v_n the guest node's speed away from its hosts along the push, c this value, N s/m per contact; 0: none. Not used by projection and volume."),
      key("contact", "response", KeyType::string).optional().range(1, kInf).schema({{"pattern", "^plugin:."}}).described("\"plugin:PATH\": the pair's contact forces from a response of your own, a shared library built against core/plugin/harness/response.h (docs/plugins.md), instead of the force rule: it is given each (sub)step's contacts with the eliminator's pushes and both bodies' state. PATH relative to the scene file. Symplectic Euler only; not with projection, volume or --device. Default: none (the force rule)."),
      key("contact", "response_parameters", KeyType::numbers).optional().described("Named numbers handed to the response's plug-in when it is made (its own names; it refuses those it does not know). Only with response. Default: none."),
  };
  append_force_keys(keys);
  return keys;
  }();
  return table;
}

namespace {

// The body's schema beyond its keys: a shell (a surface shape, fill absent or shell) takes
// material.thickness exactly when it gives youngs_modulus; a volume takes none. The shell shapes
// and the shell word from their tables (ShapeType, FillWord).
json shell_body_schema() {
  json shells = json::array();
  for (const auto& [t, w] : scene_words<ShapeType>())
    if (t != ShapeType::box) shells.push_back(w);
  json j = json::parse(R"J({"if": {"description": "The body is a shell: not a box, fill absent or shell.", "properties": {"shape": {"properties": {"type": {"enum": []}, "fill": {"const": ""}}, "required": ["type"]}}, "required": ["shape"]}, "then": {"properties": {"material": {"if": {"required": ["youngs_modulus"]}, "then": {"required": ["thickness"]}, "else": {"not": {"required": ["thickness"]}}}}}, "else": {"properties": {"material": {"not": {"required": ["thickness"]}}}}})J");
  json& shape = j["if"]["properties"]["shape"]["properties"];
  shape["type"]["enum"] = shells;
  shape["fill"]["const"] = scene_word(FillWord::shell);
  return j;
}

// The force key's kind and one kind per object rule (append_force_keys).
void append_force_kinds(std::vector<SceneKind>& kinds) {
  kinds.push_back({"force", "", "", json::object()});
  for (const ForceRuleDef& r : force_rules())
    if (r.form == RuleForm::object)
      kinds.push_back({kept(std::string("force.") + r.name), "", std::string("Force rule ") + r.name + ": " + r.doc + ".", json::object()});
}

}  // namespace

const std::vector<SceneKind>& scene_kinds() {
  static const std::vector<SceneKind> table = [] {
  std::vector<SceneKind> kinds = {
      {"scene", "", "A scene of the harness (docs/scenes.md): one JSON object in SI units (m, kg, s, N, Pa). This schema is generated from the loader's key table (core/scene/keys.cpp) for unknown keys, types, missing keys and ranges; the checks it cannot express (unique body names, contact bodies that exist, min below max, node budgets, mesh files) are listed in docs/scenes.md, \"JSON Schema\". Printed by `harness schema`.", json::object()},
      {"time", "", "", json::object()},
      {"settle", "", "", json::object()},
      {"references", "", "", json::object()},
      {"output", "", "", json::object()},
      {"body", "body", "A soft body.", shell_body_schema()},
      {"shape", "shape", "The body's geometry, chosen by `type`; each type takes only its own keys.", json::object()},
      {"shape.box", "", "", json::object(), "shape"},
      {"shape.sphere", "", "", json::object(), "shape"},
      {"shape.ellipsoid", "", "", json::object(), "shape"},
      {"shape.cylinder", "", "", json::object(), "shape"},
      {"shape.mesh", "", "", json::object(), "shape"},
      {"material", "material", "The body's material. Default: {} (density 1000, stiffness 100, linear law, no damping).", json::parse(R"J({"not": {"description": "stiffness (N/m per spring) and youngs_modulus (Pa) exclude each other.", "required": ["stiffness", "youngs_modulus"]}})J")},
      {"selection", "selection", "Exactly one of {\"side\": face} (nodes on that face of the rest bounding box), {\"box\": {\"min\", \"max\"}} (rest positions inside, inclusive) or {\"all\": true}.", json::parse(R"J({"oneOf": [{"required": ["side"]}, {"required": ["box"]}, {"required": ["all"]}]})J")},
      {"selection.box", "", "", json::object()},
      {"driver", "driver", "Nodes moved kinematically at `velocity` on steps from_step..to_step (1-based), released afterwards with their last velocity; a pin wins over a driver.", json::object()},
      {"load", "load", "A total force shared equally by the selected nodes, ramped linearly from zero.", json::object()},
      {"pressure", "pressure", "Internal pressure of a closed shell, ramped linearly from `from` to `to`.", json::object()},
      {"contact", "contact", "A contact pair: the guest's nodes are looked up against the host.", json::object()},
  };
  append_force_kinds(kinds);
  return kinds;
  }();
  return table;
}

const SceneKey& scene_key(const std::string& kind, const std::string& name) {
  for (const SceneKey& k : scene_keys())
    if (kind == k.kind && name == k.name) return k;
  throw std::logic_error("scene key " + kind + "." + name + " is not in the key table (core/scene/keys.cpp)");
}

const SceneKind& scene_kind(const std::string& kind) {
  for (const SceneKind& k : scene_kinds())
    if (kind == k.name) return k;
  throw std::logic_error("scene kind " + kind + " is not in the key table (core/scene/keys.cpp)");
}

std::vector<std::pair<std::string, const SceneKind*>> scene_variants(const std::string& kind) {
  std::vector<std::pair<std::string, const SceneKind*>> out;
  for (const SceneKind& k : scene_kinds())
    if (kind == k.variant_of) out.emplace_back(std::string(k.name).substr(kind.size() + 1), &k);
  return out;
}

}  // namespace harness
