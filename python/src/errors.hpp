// Python exceptions for locus::Error.
//
// locus.Error is the base; each ErrorCode maps to one subclass so that a
// script can catch what it can handle: InputError (the mesh is unsuitable:
// NaN positions, out-of-range or degenerate faces, non-manifold), NumericalError
// (an operator is not positive definite), Cancelled (the progress callback
// asked to stop), ResourceLimitError (also a MemoryError), UsageError (a wrong
// argument; also a ValueError, so `except ValueError` catches bad arguments
// whether the binding or the engine found them). The instance carries the
// engine's message and where it happened: .code, .vertex, .column (-1 when
// not applicable).
#pragma once
#include <pybind11/pybind11.h>

#include "locus/error.hpp"

namespace locus::python {

void register_errors(pybind11::module_& m);

// Raises the Python exception for `e` (sets the error indicator).
void set_python_error(const Error& e);

// A wrong argument found by the binding: ValueError with `message`.
[[noreturn]] void usage_error(const std::string& message);
// Bad mesh content found by the binding (e.g. an int64 vertex id beyond int32): InputError.
[[noreturn]] void input_error(const std::string& message);

}  // namespace locus::python
