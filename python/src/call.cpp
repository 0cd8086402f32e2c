// Running an engine call from Python with the GIL released, Ctrl-C as the
// cancel flag and the progress callback (issue 25 item 3); call.hpp says how.
#include "call.hpp"

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <exception>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include <Python.h>
#include <pythread.h>

namespace py = pybind11;

namespace locus::python {
namespace {

unsigned long g_main_thread = 0;  // threading.main_thread().ident

// The state one call shares between its caller, its helper thread and the
// engine's worker threads.
struct CallState {
  std::atomic<bool> cancel{false};
  std::mutex mu;
  std::exception_ptr callback_error;  // first exception raised by the progress callback
  bool callback_cancelled = false;    // the callback returned a true value

  void relay_progress(const py::object& callback, double fraction, std::string_view phase) {
    if (cancel.load(std::memory_order_relaxed)) return;
    py::gil_scoped_acquire gil;
    try {
      const py::object answer = callback(fraction, py::str(phase.data(), phase.size()));
      if (!answer.is_none() && PyObject_IsTrue(answer.ptr()) == 1) {
        std::lock_guard<std::mutex> lock(mu);
        callback_cancelled = true;
        cancel = true;
      }
    } catch (...) {
      std::lock_guard<std::mutex> lock(mu);
      if (!callback_error) callback_error = std::current_exception();
      cancel = true;
    }
  }
};

// Runs `work` on a helper thread; the caller (the main thread, GIL released)
// polls Python's signal handlers every 10 ms. Returns the pending Python
// exception a handler raised (KeyboardInterrupt), if any.
std::optional<py::error_already_set> run_watching_signals(CallState& st, const std::function<void()>& work) {
  std::mutex mu;
  std::condition_variable cv;
  bool done = false;
  std::optional<py::error_already_set> interrupted;
  py::gil_scoped_release release;
  std::thread helper([&] {
    work();
    std::lock_guard<std::mutex> lock(mu);
    done = true;
    cv.notify_one();
  });
  std::unique_lock<std::mutex> lock(mu);
  while (!cv.wait_for(lock, std::chrono::milliseconds(10), [&] { return done; })) {
    if (interrupted) continue;  // cancel raised; wait for the work to notice it
    lock.unlock();
    {
      py::gil_scoped_acquire gil;
      if (PyErr_CheckSignals() != 0) {
        interrupted.emplace();  // fetches (and clears) the pending exception
        st.cancel = true;
      }
    }
    lock.lock();
  }
  lock.unlock();
  helper.join();
  return interrupted;
}

}  // namespace

void run(const CallOptions& opt, const std::function<void(const RunContext&)>& work) {
  CallState st;
  RunContext ctx;
  ctx.threads = opt.threads;
  ctx.cancel = &st.cancel;
  if (opt.progress && !opt.progress.is_none()) {
    // By pointer: the engine copies RunContexts on worker threads without
    // the GIL, where copying a py::object (a reference count) would race.
    const py::object* callback = &opt.progress;
    ctx.progress = [&st, callback](double fraction, std::string_view phase) {
      st.relay_progress(*callback, fraction, phase);
    };
  }
  std::exception_ptr engine_error;
  const auto guarded = [&] {
    try {
      work(ctx);
    } catch (...) {
      engine_error = std::current_exception();
    }
  };
  std::optional<py::error_already_set> interrupted;
  if (PyThread_get_thread_ident() == g_main_thread) {
    interrupted = run_watching_signals(st, guarded);
  } else {
    py::gil_scoped_release release;
    guarded();
  }
  // The caller holds the GIL again. Ctrl-C first, then the callback's own
  // exception, then the engine's error (Cancelled when the callback asked).
  if (interrupted) throw std::move(*interrupted);
  if (st.callback_error) std::rethrow_exception(st.callback_error);
  if (engine_error) std::rethrow_exception(engine_error);
}

void register_call(py::module_& m) {
  g_main_thread = py::module_::import("threading").attr("main_thread")().attr("ident").cast<unsigned long>();
  (void)m;
}

}  // namespace locus::python
