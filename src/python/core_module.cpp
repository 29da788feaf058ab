// occlusion_env._core: the in-process environment and the vector environment for the Python
// package occlusion_env (python/occlusion_env; doc/PYTHON.md). The Gymnasium API is in Python;
// this module only moves data: no copies of the RGB image, depth re-encoded inside the objects'
// footprint only, the GIL released while rendering.
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "observation_views.hpp"
#include "occlusion_env/common/errors.hpp"
#include "python_environment.hpp"
#include "python_vector_environment.hpp"

namespace py = pybind11;
using namespace occlusion_env;
using namespace occlusion_env::python;

namespace {

/// The core's exception types as Python exceptions (subclasses of the built-in ones Python code
/// expects: ValueError for a bad argument, RuntimeError for the wrong time, ...).
void registerExceptions(py::module_& m) {
  py::register_exception<InvalidArgumentError>(m, "InvalidArgumentError", PyExc_ValueError);
  py::register_exception<InvalidStateError>(m, "InvalidStateError", PyExc_RuntimeError);
  py::register_exception<CatalogError>(m, "CatalogError", PyExc_RuntimeError);
  py::register_exception<RenderError>(m, "RenderError", PyExc_RuntimeError);
  py::register_exception<SceneGenerationError>(m, "SceneGenerationError", PyExc_RuntimeError);
  py::register_exception<EnvironmentUnavailableError>(m, "EnvironmentUnavailableError",
                                                      PyExc_ConnectionError);
}

}  // namespace

PYBIND11_MODULE(_core, m) {
  m.doc() = "The C++ core of occlusion_env (use occlusion_env.make, not this module)";
  registerExceptions(m);
  m.attr("MAX_DEPTH_M") = kMaxDepthM;

  m.def(
      "default_options_json",
      [](const std::string& options_json) {
        return environmentOptionTable().toJson(environmentOptionsFromJson(options_json)).dump();
      },
      py::arg("options_json") = "{}",
      "Every option (sim.yaml names) as JSON, after applying and validating `options_json`.");

  py::class_<PythonEnvironment>(m, "Environment")
      .def(py::init<const std::string&>(), py::arg("options_json"))
      .def("reset", &PythonEnvironment::reset, py::arg("seed"), py::arg("overrides"))
      .def("step", &PythonEnvironment::step, py::arg("action"))
      .def("options_json", &PythonEnvironment::optionsJson);

  py::class_<PythonVectorEnvironment>(m, "VectorEnvironment")
      .def(py::init<int, const std::string&>(), py::arg("count"), py::arg("options_json"))
      .def("run", &PythonVectorEnvironment::run, py::arg("kinds"), py::arg("seeds"),
           py::arg("actions"), py::arg("overrides"))
      .def("arrays", &PythonVectorEnvironment::arrays)
      .def("size", &PythonVectorEnvironment::size)
      .def("options_json", &PythonVectorEnvironment::optionsJson);
}
