// The Python module's C++ side (docs/python.md): the scene (module_scene.cpp), the simulation
// one can step (module_sim.cpp), the run and the module itself (module.cpp). The pure-Python part
// (python/harness/__init__.py) wraps these into the public API.
#pragma once

#include "core/collision/collision.hpp"
#include "core/collision/detectors/collision_detector.hpp"
#include "core/scene/scene.hpp"

#include <pybind11/pybind11.h>

#include <memory>
#include <vector>

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

// Python callables as contact responses (module_response.cpp): `response` is None, a callable (for
// every pair) or a dict of pair label or index -> callable; each is called with (contacts, guest,
// host) and returns (forces on the guest, forces on the host). A callable's first exception is kept
// in `error` (the step then fails) and raised by raise_if_any() once the GIL is held again.
struct PyResponses {
  struct Error {
    std::shared_ptr<pybind11::error_already_set> value;  // null: none
  };
  std::vector<OwnResponse> list;
  std::shared_ptr<Error> error;
  void raise_if_any();
};
PyResponses python_responses(const pyb::object& response, const Scene& scene);

void bind_scene(pyb::module_& m);
void bind_simulation(pyb::module_& m);

}  // namespace harness::py
