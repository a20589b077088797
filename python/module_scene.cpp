// harness.Scene from C++: loading (a file or a bundled name), a document from a dict, dotted-key
// edits with the command line's --set rules, step counts and dt rescaled as --steps, --dt-divide
// and --dt do. Every error is an InputError (harness.SceneError) with the CLI's exit-2 line.
#include "python/module.hpp"

#include "core/scene/bundled.hpp"

#include <filesystem>

namespace harness::py {

PyScene make_scene(SceneSource src) {
  Scene s = scene_from_source(src);
  return PyScene{std::move(src), std::move(s)};
}

// json.dumps's `default`: numpy scalars and arrays (anything with tolist()) as their Python values.
pyb::object numpy_default() {
  // Never destroyed: a Python object must not be released after the interpreter has finalized.
  static pyb::object* f = new pyb::object(pyb::cpp_function([](const pyb::handle& o) -> pyb::object {
    if (pyb::hasattr(o, "tolist")) return o.attr("tolist")();
    throw pyb::type_error(std::string("Object of type ") + pyb::str(o.get_type().attr("__name__")).cast<std::string>() +
                          " is not JSON serializable");
  }));
  return *f;
}

std::string to_json_text(const pyb::handle& value, const std::string& where) {
  try {
    return pyb::module_::import("json")
        .attr("dumps")(value, pyb::arg("allow_nan") = false, pyb::arg("default") = numpy_default())
        .cast<std::string>();
  } catch (pyb::error_already_set& e) {
    if (!e.matches(PyExc_TypeError) && !e.matches(PyExc_ValueError)) throw;
    throw InputError(where, std::string("not a JSON value: ") + e.value().attr("__str__")().cast<std::string>());
  }
}

pyb::object from_json(const nlohmann::json& j) { return pyb::module_::import("json").attr("loads")(j.dump()); }

namespace {

// A path as a string (str or os.PathLike).
std::string fspath(const pyb::object& p) { return pyb::str(pyb::module_::import("os").attr("fspath")(p)); }

// Mesh paths are relative to the scene's folder: kept absolute, so that a Scene does not depend on
// the working directory it was loaded from.
SceneSource absolute_dir(SceneSource src) {
  src.dir = std::filesystem::absolute(src.dir).lexically_normal().string();
  return src;
}

PyScene load(const pyb::object& path_or_name) {
  return make_scene(absolute_dir(read_scene_source(resolve_scene(fspath(path_or_name)))));
}

// A document from a Python dict: messages name `file` ("<dict>" unless given), mesh paths are
// relative to base_dir (default: the current folder).
PyScene from_dict(const pyb::dict& d, const std::string& file, const pyb::object& base_dir) {
  SceneSource src = parse_scene_source(to_json_text(d, file), file);
  src.dir = base_dir.is_none() ? std::filesystem::current_path().string() : fspath(base_dir);
  return make_scene(absolute_dir(std::move(src)));
}

// scene.with_(**{"contacts.0.force": 0.01}): each key's value set as --set KEY=JSON would set it
// (in the order given), then the whole document validated again.
PyScene with_values(const PyScene& s, const pyb::kwargs& values) {
  SceneSource src = s.src;
  for (const auto& [k, v] : values) {
    const std::string key = pyb::str(k);
    apply_override(src.doc, key, to_json_text(v, "--set " + key));
  }
  return make_scene(std::move(src));
}

PyScene with_edit(const PyScene& s, const std::function<void(nlohmann::json&)>& edit) {
  SceneSource src = s.src;
  edit(src.doc);
  return make_scene(std::move(src));
}

pyb::list names(const Scene& s, bool bodies) {
  pyb::list out;
  if (bodies)
    for (const BodySpec& b : s.bodies) out.append(b.name);
  else
    for (const ContactPairSpec& c : s.contacts) out.append(c.label);
  return out;
}

}  // namespace

PyScene as_scene(const pyb::object& o) {
  if (pyb::isinstance<PyScene>(o)) return o.cast<PyScene>();
  if (pyb::isinstance<pyb::dict>(o)) return from_dict(o.cast<pyb::dict>(), "<dict>", pyb::none());
  if (pyb::isinstance<pyb::str>(o) || pyb::hasattr(o, "__fspath__")) return load(o);
  throw pyb::type_error("expected a harness.Scene, a dict or a scene file/name, got " +
                        pyb::str(o.get_type().attr("__name__")).cast<std::string>());
}

void bind_scene(pyb::module_& m) {
  pyb::class_<PyScene>(m, "Scene", "A validated scene (docs/scenes.md). Immutable: edits return a new Scene.")
      .def_static("load", &load, pyb::arg("path_or_name"),
                  "A scene file, or the name of a bundled scene (harness list).")
      .def_static("from_dict", &from_dict, pyb::arg("d"), pyb::arg("file") = "<dict>", pyb::arg("base_dir") = pyb::none(),
                  "A scene from a dict of the scene format; mesh paths relative to base_dir (default: the "
                  "current folder); messages name `file`.")
      .def("with_", &with_values,
           "A new scene with values set at dotted key paths, as --set does: scene.with_(**{'contacts.0.force': 0.01}).")
      .def("with_steps", [](const PyScene& s, long long n) {
             if (n < 0) throw InputError("--steps", "must be >= 0");
             return with_edit(s, [n](nlohmann::json& d) {
               for (const auto& [k, v] : steps_overrides(n)) apply_override(d, k, v);
             });
           }, pyb::arg("n"), "Exactly n steps (time.steps = n, time.settle off), as --steps.")
      .def("with_dt_divide", [](const PyScene& s, int factor) {
             if (factor < 1) throw InputError("--dt-divide", "must be >= 1");
             return with_edit(s, [factor](nlohmann::json& d) { rescale_steps(d, factor); });
           }, pyb::arg("factor"), "dt / factor over the same physical time, as --dt-divide.")
      .def("with_dt", [](const PyScene& s, double dt) {
             return with_edit(s, [dt](nlohmann::json& d) { rescale_to_dt(d, dt); });
           }, pyb::arg("dt"), "Time step dt (s) over the same physical time, as --dt.")
      .def("to_dict", [](const PyScene& s) { return from_json(s.src.doc); },
           "The document as loaded and edited (no defaults filled in).")
      .def("resolved", [](const PyScene& s) { return from_json(s.scene.resolved); },
           "The document with every default written in (summary.json's scene).")
      .def_property_readonly("name", [](const PyScene& s) { return s.scene.name; })
      .def_property_readonly("file", [](const PyScene& s) { return s.src.file; })
      .def_property_readonly("dt", [](const PyScene& s) { return s.scene.dt; })
      .def_property_readonly("steps", [](const PyScene& s) { return s.scene.steps; })
      .def_property_readonly("bodies", [](const PyScene& s) { return names(s.scene, true); })
      .def_property_readonly("contacts", [](const PyScene& s) { return names(s.scene, false); })
      .def("__eq__", [](const PyScene& a, const PyScene& b) { return a.scene.resolved == b.scene.resolved && a.src.dir == b.src.dir; })
      .def(pyb::pickle(
          [](const PyScene& s) { return pyb::make_tuple(s.src.doc.dump(), s.src.file, s.src.dir); },
          [](const pyb::tuple& t) {
            SceneSource src{nlohmann::json::parse(t[0].cast<std::string>()), t[1].cast<std::string>(), t[2].cast<std::string>()};
            return make_scene(std::move(src));
          }))
      .def("__repr__", [](const PyScene& s) {
        return "<harness.Scene '" + s.scene.name + "' from " + s.src.file + ": " + std::to_string(s.scene.bodies.size()) +
               " bodies, " + std::to_string(s.scene.contacts.size()) + " contacts, dt " + pyb::str(pyb::float_(s.scene.dt)).cast<std::string>() +
               " s, " + std::to_string(s.scene.steps) + " steps>";
      });
}

}  // namespace harness::py
