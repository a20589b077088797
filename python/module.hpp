// The Python module's C++ side (docs/python.md): the scene (module_scene.cpp), the simulation
// one can step (module_sim.cpp), the run and the module itself (module.cpp). The pure-Python part
// (python/harness/__init__.py) wraps these into the public API.
#pragma once

#include "core/collision/detectors/collision_detector.hpp"
#include "core/scene/scene.hpp"

#include <pybind11/pybind11.h>

namespace harness::py {

namespace pyb = pybind11;

// A scene: the document as edited (what to_dict() returns and with_() edits) and the scene it
// validates into. Immutable from Python: every edit makes a new one.
struct PyScene {
  SceneSource src;
  Scene scene;
};

// Validates a document into a PyScene (InputError: SceneError in Python).
PyScene make_scene(SceneSource src);
// A Scene, a dict of the scene format, or a scene file / bundled name (str or os.PathLike) as a Scene.
PyScene as_scene(const pyb::object& o);

// The JSON text of a Python value (json.dumps, no NaN), or InputError(where, ...) when it has none.
std::string to_json_text(const pyb::handle& value, const std::string& where);
// A Python value from nlohmann JSON (json.loads of its text).
pyb::object from_json(const nlohmann::json& j);

// The reference library's makers where this build links it (HARNESS_HAVE_REFERENCE), else null.
ExactDetectorMaker exact_detector_maker();
bool have_reference();

// Raises KeyboardInterrupt (or whatever Python's signal handlers raise) when a signal arrived:
// PyErr_CheckSignals with the GIL taken. Call with the GIL released.
void check_signals();

void bind_scene(pyb::module_& m);
void bind_simulation(pyb::module_& m);

}  // namespace harness::py
