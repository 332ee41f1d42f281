// The extension module idto._idto (re-exported by the package idto): bindings of idto's C++
// API with the C++ names in snake_case. One bind_*.cpp file per part of the library.

#include "convert.hpp"

namespace idto::python {
namespace {

void RegisterExceptions(py::module_& m) {
  // idto::FileError (missing or malformed files): an OSError that is also a RuntimeError, with
  // the C++ message and the attributes `file` and `element`.
  static py::handle file_error = [&m] {
    const py::tuple bases =
        py::make_tuple(py::handle(PyExc_OSError), py::handle(PyExc_RuntimeError));
    PyObject* type = PyErr_NewException("idto.FileError", bases.ptr(), nullptr);
    m.add_object("FileError", py::handle(type));
    return py::handle(type);
  }();
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const FileError& e) {
      py::object error = py::reinterpret_borrow<py::object>(file_error)(e.what());
      error.attr("file") = e.file();
      error.attr("element") = e.element();
      PyErr_SetObject(file_error.ptr(), error.ptr());
    } catch (const InvalidArgument& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    }
  });
}

}  // namespace
}  // namespace idto::python

PYBIND11_MODULE(_idto, m) {
  namespace ip = idto::python;
  m.doc() = "idto: Inverse Dynamics Trajectory Optimization (C++ bindings)";
  m.attr("__version__") = IDTO_VERSION_STRING;
  ip::RecordMainThread();
  ip::RegisterExceptions(m);
  ip::BindModel(m);
  ip::BindProblem(m);
  ip::BindSolver(m);
  ip::BindConfig(m);
  ip::BindMpc(m);
  ip::BindSim(m);
  pybind11::module_ testing = m.def_submodule("_testing", "C++ helpers for tests and benchmarks");
  ip::BindTesting(testing);
}
