// Python exceptions for locus::Error; errors.hpp says which.
#include "errors.hpp"

#include <Python.h>

namespace py = pybind11;

namespace locus::python {
namespace {

// The classes, created once at import (module attributes keep them alive).
PyObject* g_error = nullptr;
PyObject* g_usage = nullptr;
PyObject* g_input = nullptr;
PyObject* g_numerical = nullptr;
PyObject* g_cancelled = nullptr;
PyObject* g_resource = nullptr;

PyObject* make_class(py::module_& m, const char* name, const char* doc, py::tuple bases) {
  const std::string qualified = std::string("locus.") + name;
  PyObject* cls = PyErr_NewExceptionWithDoc(qualified.c_str(), doc, bases.ptr(), nullptr);
  if (!cls) throw py::error_already_set();
  m.add_object(name, py::reinterpret_borrow<py::object>(cls));
  return cls;
}

PyObject* class_of(ErrorCode code) {
  switch (code) {
    case ErrorCode::BadUsage: return g_usage;
    case ErrorCode::BadInput: return g_input;
    case ErrorCode::Numerical: return g_numerical;
    case ErrorCode::Cancelled: return g_cancelled;
    case ErrorCode::ResourceLimit: return g_resource;
    case ErrorCode::Internal: return g_error;
  }
  return g_error;
}

void raise(PyObject* cls, const std::string& message, int code, int64_t vertex, int64_t column) {
  py::object instance = py::reinterpret_borrow<py::object>(cls)(message);
  instance.attr("code") = code;
  instance.attr("vertex") = vertex;
  instance.attr("column") = column;
  PyErr_SetObject(cls, instance.ptr());
}

}  // namespace

void set_python_error(const Error& e) {
  raise(class_of(e.code()), e.what(), static_cast<int>(e.code()), e.where().vertex, e.where().column);
}

void usage_error(const std::string& message) {
  raise(g_usage, message, static_cast<int>(ErrorCode::BadUsage), -1, -1);
  throw py::error_already_set();
}

void input_error(const std::string& message) {
  raise(g_input, message, static_cast<int>(ErrorCode::BadInput), -1, -1);
  throw py::error_already_set();
}

void register_errors(py::module_& m) {
  const py::object exception = py::reinterpret_borrow<py::object>(PyExc_Exception);
  g_error = make_class(m, "Error",
                       "Base of locus' exceptions. Attributes: code (the CLI's exit status: 2 usage, 3 input, "
                       "4 numerical, 5 cancelled, 6 resource limit, 70 internal), vertex and column (where, "
                       "or -1).",
                       py::make_tuple(exception));
  const py::object base = py::reinterpret_borrow<py::object>(g_error);
  g_usage = make_class(m, "UsageError", "A wrong argument (also a ValueError): a vertex id out of range, a "
                       "fraction outside (0, 1], an array of the wrong shape or dtype.",
                       py::make_tuple(base, py::reinterpret_borrow<py::object>(PyExc_ValueError)));
  g_input = make_class(m, "InputError", "The mesh is unsuitable: non-finite positions, faces referencing missing "
                       "vertices, degenerate or non-manifold faces, unreadable files.", py::make_tuple(base));
  g_numerical = make_class(m, "NumericalError", "An operator is not positive definite (the message names the "
                           "vertex and factor column) or a result is not finite.", py::make_tuple(base));
  g_cancelled = make_class(m, "Cancelled", "The call was cancelled: the progress callback returned True. "
                           "(Ctrl-C cancels too, and raises KeyboardInterrupt.)", py::make_tuple(base));
  g_resource = make_class(m, "ResourceLimitError", "A factorization would exceed the memory limit (also a "
                          "MemoryError).",
                          py::make_tuple(base, py::reinterpret_borrow<py::object>(PyExc_MemoryError)));
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const Error& e) {
      set_python_error(e);
    }
  });
}

}  // namespace locus::python
