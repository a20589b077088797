// The extension module harness._harness (docs/python.md): Scene, Simulation, and run_scene
// (`harness run` itself, writing the same files), with InputError raised as harness.SceneError.
#include "python/module.hpp"

#include "core/parallel.hpp"
#include "core/run/run_scene.hpp"

#ifdef HARNESS_HAVE_REFERENCE
#include "reference/reference.hpp"
#endif

namespace harness::py {

ExactDetectorMaker exact_detector_maker() {
#ifdef HARNESS_HAVE_REFERENCE
  return make_exact_detector;
#else
  return nullptr;
#endif
}

bool have_reference() { return exact_detector_maker() != nullptr; }

void check_signals() {
  pyb::gil_scoped_acquire acquire;
  if (PyErr_CheckSignals() != 0) throw pyb::error_already_set();
}

namespace {

// `harness run` on a scene into out_dir: the same options as the command line's, no progress
// line. Returns its exit status (0 done, 3 non-finite, 130/143 interrupted: harness.run raises).
int run_scene_into(const PyScene& s, const std::string& out_dir, int threads, const std::string& compare,
                   const std::string& compare_also, const pybind11::object& response) {
  if (threads < 1) throw pyb::value_error("threads: must be >= 1");
#ifdef HARNESS_HAVE_REFERENCE
  RunOptions opt = with_references();
#else
  RunOptions opt;
#endif
  opt.out_dir = out_dir;
  opt.progress = false;
  opt.compare_dir = compare;
  opt.compare_also_dir = compare_also;
  PyResponses responses = python_responses(response, s.scene);
  opt.responses = responses.list;
  const int before = harness::threads();
  set_threads(threads);
  int rc = 0;
  try {
    pyb::gil_scoped_release release;
    rc = run_scene(s.scene, opt);
  } catch (...) {
    set_threads(before);
    throw;
  }
  set_threads(before);
  responses.raise_if_any();  // a response's own exception, once the run's outputs are written
  return rc;
}

}  // namespace

}  // namespace harness::py

PYBIND11_MODULE(_harness, m) {
  using namespace harness::py;
  m.doc() = "harness: soft bodies as nonlinear mass-spring models, collisions by the local voxel model "
            "(the C++ side of the Python module; import harness)";
  // SceneError: the CLI's exit-2 line (without "harness: error: "); bytes that are not UTF-8 (a
  // message quoting a Latin-1 file) kept as backslash escapes, never an empty message.
  static auto* scene_error = new pybind11::exception<harness::InputError>(m, "SceneError", PyExc_ValueError);
  pybind11::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const harness::InputError& e) {
      const std::string what = e.what();
      pybind11::object msg = pybind11::reinterpret_steal<pybind11::object>(
          PyUnicode_DecodeUTF8(what.data(), static_cast<Py_ssize_t>(what.size()), "backslashreplace"));
      PyErr_SetObject(scene_error->ptr(), msg.ptr());
    }
  });
  bind_scene(m);
  bind_simulation(m);
  m.def("_run_scene", &run_scene_into, pybind11::arg("scene"), pybind11::arg("out_dir"), pybind11::arg("threads") = 1,
        pybind11::arg("compare") = "", pybind11::arg("compare_also") = "", pybind11::arg("response") = pybind11::none());
  m.def("have_reference", &have_reference, "Whether this build links FCL and CGAL (references, measure()).");
}
