// The `locus._locus` extension module: NumPy in and out of the
// engine's Session, the GIL released while computing, Ctrl-C as the cancel
// flag, engine errors as Python exceptions. python/locus/__init__.py re-exports
// it with the one-shot functions (python/locus/_one_shot.py).
#include <pybind11/pybind11.h>

#include "call.hpp"
#include "errors.hpp"
#include "session_bindings.hpp"

#include "locus/version.h"

namespace locus::python {
void bind_mesh_functions(pybind11::module_& m);  // mesh_functions.cpp
void bind_bench_peer(pybind11::module_& m);      // bench_peer.cpp
void bind_request_fields(pybind11::module_& m);  // session_commands.cpp
}

PYBIND11_MODULE(_locus, m) {
  m.doc() = "locus engine bindings (see the package locus)";
  // Each docstring opens with its Python signature, defaults included;
  // pybind11's generated one would repeat it with C++ type names.
  pybind11::options options;
  options.disable_function_signatures();
  m.attr("__version__") = LOCUS_VERSION_STRING;
  locus::python::register_errors(m);
  locus::python::register_call(m);
  locus::python::bind_session(m);
  locus::python::bind_mesh_functions(m);
  locus::python::bind_bench_peer(m);
  locus::python::bind_request_fields(m);
}
