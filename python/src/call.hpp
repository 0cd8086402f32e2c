// Running an engine call from Python (issue 25 item 3): the GIL released for
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

// What every computing method takes as keyword arguments.
struct CallOptions {
  int threads = 0;              // worker threads for this call; 0 = all cores
  pybind11::object progress;    // None or callable(fraction: float, phase: str) -> bool | None
};

// Runs work(ctx) with the GIL released and returns when it is done.
//  * From the main thread, the work runs on a helper thread while the caller
//    waits in 10 ms slices, taking the GIL between slices only to run Python's
//    signal handlers (PyErr_CheckSignals). A pending KeyboardInterrupt (or any
//    exception a signal handler raises) raises the call's cancel flag; the work
//    stops at the engine's next cancel check (the factorization checks before
//    every supernode), the helper is joined, and the KeyboardInterrupt is
//    raised. Why not a temporary SIGINT handler: a C handler would replace the
//    interpreter's own (and any the script installed) process-wide, racing
//    with other threads doing the same; waiting in slices keeps Python's
//    signal machinery untouched and costs one thread start per call
//    (benchmarked in tools/bench_python.py).
//  * From any other thread (signals are only delivered to the main thread),
//    the work runs inline with the GIL released.
//  * progress: called from whichever thread the engine reports on, with the
//    GIL taken for the call. A true return value cancels (locus.Cancelled);
//    an exception it raises cancels and is re-raised by the call.
void run(const CallOptions& opt, const std::function<void(const RunContext&)>& work);

// Registers what run() needs at import (the main thread's id).
void register_call(pybind11::module_& m);

}  // namespace locus::python
