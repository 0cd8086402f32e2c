// Running an engine call from Python: the GIL released for
// the whole computation, Ctrl-C turned into the engine's cancel flag, and the
// progress callback relayed to Python.
//
// Every binding that computes goes through run(): it builds the RunContext
// (threads, cancel flag, progress) and runs `work` with the GIL released, so
// other Python threads run meanwhile and several threads may query one Session
// at once (the Session's queries are re-entrant).
#pragma once
#include <functional>

#include <pybind11/pybind11.h>

#include "locus/run_context.hpp"

namespace locus::python {

// The largest `threads` a call takes (the CLI's --threads limit).
inline constexpr int kMaxThreads = 4096;

// What every computing method takes as keyword arguments.
struct CallOptions {
  int threads = 0;              // worker threads for this call; 0 = all cores, at most kMaxThreads (run() refuses others)
  pybind11::object progress;    // None or callable(fraction: float, phase: str) -> bool | None
};

// Runs work(ctx) with the GIL released and returns when it is done.
//  * Ctrl-C: from the main thread (the only one Python delivers
//    KeyboardInterrupt to), for the duration of the call a C SIGINT handler
//    raises this call's cancel flag and then calls the handler it replaced
//    (the interpreter's, which schedules KeyboardInterrupt), so the work stops
//    at the engine's next cancel check and the call raises KeyboardInterrupt.
//    The interpreter's handler is restored when the call returns. When the
//    replaced handler is not the interpreter's (Blender and other embedding
//    hosts install their own), the call raises KeyboardInterrupt itself:
//    Ctrl-C means KeyboardInterrupt in every host. Not
//    installed when SIGINT is ignored or default (the script chose that).
//    Why not run the work on a helper thread while the caller polls
//    PyErr_CheckSignals: it was measured (tools/bench_python.py, docs/python.md)
//    to cost two thread hand-offs per call, 12 ms per geodesic query on the
//    loaded 2-core machine (against a 3.4 ms query); the handler costs two
//    sigaction calls.
//  * Every thread runs the work inline.
//  * progress: called from whichever thread the engine reports on, with the
//    GIL taken for the call. A true return value cancels (locus.Cancelled);
//    an exception it raises cancels and is re-raised by the call.
void run(const CallOptions& opt, const std::function<void(const RunContext&)>& work);

// Registers what run() needs at import (the main thread's id).
void register_call(pybind11::module_& m);

}  // namespace locus::python
