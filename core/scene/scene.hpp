// Scene format (docs/scenes.md): one JSON object, SI units, validated strictly and once. Every
// bad input throws InputError naming the file and the key path (or line and column for malformed
// JSON). Defaults are written into `resolved`, which the run records in summary.json.
//
// The files: keys.{hpp,cpp} (the table of keys: types, ranges, defaults, units, names, step
// counts), check.{hpp,cpp} (the JSON checking toolkit), readers.cpp (the section readers: JSON
// into a Scene), document.cpp (the document before validation: parsing, file I/O, --set, step
// rescaling), schema.{hpp,cpp} (the JSON Schema, generated from the table).
#pragma once

#include "core/scene/contact_spec.hpp"
#include "core/scene/reference_spec.hpp"
#include "core/scene/keys.hpp"
#include "core/types.hpp"
#include "core/world.hpp"

#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace harness {

// Effects a scene may list; exactly the listed ones are simulated (effects/effects.hpp has the
// table of their names and makers).
enum EffectFlag : unsigned {
  kSprings = 1u << 0,
  kDamping = 1u << 1,
  kGravity = 1u << 2,
  kPins = 1u << 3,
  kDrivers = 1u << 4,
  kPressure = 1u << 5,
  kContact = 1u << 6,
  kLoads = 1u << 7,
  kBulk = 1u << 8,
};
// (flag, name) of every effect: the scene's words for them, in the order a step evaluates them
// (core/effects/effects.cpp's table makes each in this order, and a test checks that it does).
std::vector<std::pair<EffectFlag, const char*>> effect_names();
const char* effect_name(EffectFlag e);

struct Selection {
  enum Kind { side, box, all } kind = all;
  int axis = 0;  // side: 0,1,2 for x,y,z
  int sign = 1;  // side: -1 or +1
  Vec3 min = Vec3::Zero(), max = Vec3::Zero();  // box: rest position inside (inclusive)
  std::string path;  // key path, for errors
};

// The section structs below have no default values of their own: the loader fills every field
// from its row of the key table (keys.cpp), a missing key with the row's default
// (tests/core/scene/test_defaults.cpp builds each from an empty section and compares). Their
// members are zero until then.
struct DriverSpec {
  Selection select;
  Vec3 velocity = Vec3::Zero();  // m/s
  int from_step = 0;             // first step (1-based step numbers) that is driven
  int to_step = 0;               // last driven step; -1 = until the end
};

struct PressureSpec {
  bool present = false;
  double from = 0.0, to = 0.0;  // Pa
  int ramp_steps = 0;           // linear ramp from `from` to `to` over this many steps
};

// A force applied to a selection of a body's nodes (effect "loads"): `force` is the total in N,
// shared equally among the selected nodes, ramped linearly from zero over ramp_steps steps.
struct LoadSpec {
  Selection select;
  Vec3 force = Vec3::Zero();
  int ramp_steps = 0;
};

// Equilibrium (time.settle): after time.steps, the run goes on until the relative force
// residual is at most `tolerance` for kSettleWindow steps in a row, or max_steps more steps.
constexpr int kSettleWindow = 100;
struct SettleSpec {
  bool present = false;
  double tolerance = 0.0;
  int max_steps = 0;
};

struct ShapeSpec {
  ShapeType type = ShapeType::box;
  Vec3 min = Vec3::Zero(), max = Vec3::Zero();
  Vec3i cells = Vec3i::Zero();
  bool alternating_diagonals = false;  // box: surface quads split along alternating diagonals
  Vec3 center = Vec3::Zero();
  double radius = 0.0;
  Vec3 radii = Vec3::Zero();
  int subdivisions = 0;
  Vec3 axis = Vec3::Zero();
  double length = 0.0;
  int segments = 0, rings = 0;
  std::string path;      // mesh: resolved absolute or scene-relative path
  double scale = 0.0;
  Vec3 translate = Vec3::Zero();
  bool volume_fill = false;
};

struct BodySpec {
  std::string name;
  ShapeSpec shape;
  Material material;
  Vec3 velocity = Vec3::Zero();
  std::vector<Selection> pins;
  std::vector<DriverSpec> drivers;
  PressureSpec pressure;
  std::vector<LoadSpec> loads;
  std::string path;  // "bodies.N"
};

struct ContactPairSpec {
  std::string host, guest;  // body names, as the scene gives them
  std::string label;        // the pair's name in the outputs (default "host/guest")
  ContactSpec spec{};       // the pair's parameters; host and guest are the bodies' indices
  std::string path;         // "contacts.N"
  // contacts.N.response: a plug-in's file (the PATH of "plugin:PATH", resolved against the scene's
  // directory; "" the force rule) and its response_parameters in the scene's order.
  std::string plugin;
  std::vector<std::pair<std::string, double>> plugin_parameters;
};

struct Scene {
  std::string file;  // where it was read from (for messages)
  std::string dir;   // directory mesh paths are relative to
  std::string name;
  std::optional<long long> seed;
  double dt = 0.0;
  int steps = 0;
  Integrator integrator{};
  Guard guard{};
  double cg_tolerance = 1e-6;  // time.cg_tolerance: implicit_euler's CG relative residual
  int max_substeps = 1000;     // time.max_substeps: the guard's cap (stability.hpp)
  SettleSpec settle;
  // time.window: the run is judged over its final `window` steps after every driver, load and
  // pressure ramp has finished (run/window.hpp).
  int window = 0;
  unsigned effects = 0;
  Vec3 gravity = Vec3::Zero();
  std::vector<BodySpec> bodies;
  std::vector<ContactPairSpec> contacts;
  ReferenceSpec references;
  int frames_every = 0;
  // output.format: frames as VTK XML PolyData .vtp (default), XML UnstructuredGrid .vtu (what
  // meshio reads), or legacy ASCII .vtk; the XML ones with a ParaView collection per body.
  FrameFormat frame_format{};
  bool trajectory = false;  // output.trajectory: DIR/trajectory.bin (run/surfaces.hpp)
  nlohmann::json resolved;  // the scene with every default written in
  // What the command line's edits changed beyond what was asked (rescale_to_dt's rounded counts):
  // a run prints each as a warning, records it in summary.json `warnings`, refuses it with --strict.
  std::vector<std::string> edit_warnings;

  bool has(EffectFlag e) const { return (effects & e) != 0; }
};

// A scene document before validation: the parsed JSON, the file it came from (for messages) and
// the folder mesh paths are relative to. The command line edits it (--set, --steps, --dt-divide,
// --dt), and so do the reference levels; it is validated once, into a Scene.
struct SceneSource {
  nlohmann::json doc;
  std::string file, dir;
};
// Parses JSON text (errors as "file:line:col: ...", duplicate keys refused).
SceneSource parse_scene_source(const std::string& text, const std::string& file);
// Reads the file then parse_scene_source. Throws InputError if unreadable.
SceneSource read_scene_source(const std::string& path);
// Validates the document into a Scene (scene_from_json).
Scene scene_from_source(const SceneSource& src);

// Parses JSON text, applies the overrides (apply_override, in order), validates.
Scene parse_scene(const std::string& text, const std::string& file,
                  const std::vector<std::pair<std::string, std::string>>& overrides = {});
// Reads the file then parse_scene. Throws InputError if unreadable.
Scene load_scene(const std::string& path,
                 const std::vector<std::pair<std::string, std::string>>& overrides = {});
// Validates an already parsed JSON document (used by parse_scene and by tests).
Scene scene_from_json(const nlohmann::json& doc, const std::string& file, const std::string& dir);

// Sets the value at a dotted key path with list indices ("contacts.0.force"), creating
// missing object members; `value_json` is a JSON literal (a bare word is a string). Throws
// InputError("--set KEY", ...).
void apply_override(nlohmann::json& doc, const std::string& key, const std::string& value_json);
// --steps N: exactly N steps, as overrides (time.steps = N, time.settle = null).
std::vector<std::pair<std::string, std::string>> steps_overrides(long long steps);

// The same scene at dt / factor over the same physical time, as an edit of the document: every
// key that counts steps (the key table's, keys.hpp: time.steps, time.window,
// time.settle.max_steps, pressure and load ramps, driver windows, references.every,
// output.frames_every) times factor, a key left out at its default too; step k at dt covers
// steps (k-1) factor + 1 .. k factor. Values the loader would refuse are left for it to report.
void rescale_steps(nlohmann::json& doc, int factor);
// The same scene at time step `dt` (s) over the same physical time: every step count times
// ratio = the scene's time.dt / dt, exactly when the ratio is whole (rescale_steps), rounded to
// the nearest count (at least 1) otherwise; then time.dt = dt. Throws InputError("--dt", ...) for
// a dt that is not positive or is more than 1e6 times off. Returns one line per count of the scene's
// forcing (drivers' steps, load and pressure ramps) the ratio did not carry to a whole number
// ("KEY.PATH: N steps at the scene's time.dt are X at --dt, rounded to M (...)"): there the forcing
// changes (a driver's travel, a ramp's length); a run warns of each (Scene::edit_warnings).
std::vector<std::string> rescale_to_dt(nlohmann::json& doc, double dt);
// rescale_steps on a validated scene's resolved document, validated again (tests).
Scene rescale_dt(const Scene& scene, int factor);

// A contact pair's parameters at the key table's defaults (rows "contact.*"), read as the loader
// reads a contact that gives none of them; host and guest -1. The one way, with the loader, to
// make a ContactSpec (ContactSpec::made): set its fields after.
ContactSpec contact_spec_defaults();
// A body's material and a references section at the key table's defaults (rows "material.*",
// "references.*"), read as the loader reads an empty section: the ways, with the loader, to make
// one for a body or a measurement built by hand (tests, experiments).
Material material_defaults();
ReferenceSpec reference_spec_defaults();

// Reads a whole text file; throws InputError(path, ...) when missing or unreadable.
std::string read_text_file(const std::string& path);

}  // namespace harness
