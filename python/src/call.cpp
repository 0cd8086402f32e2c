// Running an engine call from Python with the GIL released, Ctrl-C as the
// cancel flag and the progress callback; call.hpp says how.
#include "call.hpp"
#include "errors.hpp"

#include <signal.h>

#include <atomic>
#include <exception>
#include <mutex>
#include <optional>
#include <string>

#include <Python.h>
#include <pythread.h>

namespace py = pybind11;

namespace locus::python {
namespace {

unsigned long g_main_thread = 0;  // threading.main_thread().ident

// The state one call shares between its caller, the engine's worker threads
// and the SIGINT handler.
struct CallState {
  std::atomic<bool> cancel{false};
  std::atomic<bool> interrupted{false};  // SIGINT arrived during the call
  std::mutex mu;
  std::exception_ptr callback_error;  // first exception raised by the progress callback

  void relay_progress(const py::object& callback, double fraction, std::string_view phase) {
    if (cancel.load(std::memory_order_relaxed)) return;
    py::gil_scoped_acquire gil;
    try {
      const py::object answer = callback(fraction, py::str(phase.data(), phase.size()));
      if (!answer.is_none() && PyObject_IsTrue(answer.ptr()) == 1) cancel = true;
    } catch (...) {
      std::lock_guard<std::mutex> lock(mu);
      if (!callback_error) callback_error = std::current_exception();
      cancel = true;
    }
  }
};

// The call the handler cancels (the innermost main-thread call), and the
// handler it chains to. Written by the main thread only, before the handler
// is installed or after it is removed; read by the handler (lock-free atomics,
// async-signal-safe).
std::atomic<CallState*> g_sigint_target{nullptr};
struct sigaction g_chained {};
static_assert(std::atomic<CallState*>::is_always_lock_free);

void on_sigint(int sig, siginfo_t* info, void* context) {
  if (CallState* st = g_sigint_target.load()) {
    st->interrupted.store(true);
    st->cancel.store(true);
  }
  if (g_chained.sa_flags & SA_SIGINFO) g_chained.sa_sigaction(sig, info, context);
  else if (g_chained.sa_handler != SIG_DFL && g_chained.sa_handler != SIG_IGN) g_chained.sa_handler(sig);
}

// For the lifetime of a main-thread call: SIGINT cancels it (call.hpp).
// Calls nest (a progress callback may call locus again): the outermost scope
// installs the handler, each scope points it at its own call.
class SigintScope {
 public:
  explicit SigintScope(CallState& st) : previous_target_(g_sigint_target.load()) {
    struct sigaction current {};
    sigaction(SIGINT, nullptr, &current);
    const bool ours = (current.sa_flags & SA_SIGINFO) && current.sa_sigaction == &on_sigint;
    if (!ours) {
      const bool function = (current.sa_flags & SA_SIGINFO) ||
                            (current.sa_handler != SIG_DFL && current.sa_handler != SIG_IGN);
      if (!function) return;  // ignored or default: the script's choice, left alone
      g_chained = current;
      struct sigaction mine {};
      mine.sa_sigaction = &on_sigint;
      mine.sa_flags = SA_SIGINFO | SA_ONSTACK | SA_RESTART;
      sigemptyset(&mine.sa_mask);
      installed_ = sigaction(SIGINT, &mine, nullptr) == 0;
    }
    g_sigint_target.store(&st);
    active_ = true;
  }
  ~SigintScope() {
    if (!active_) return;
    g_sigint_target.store(previous_target_);
    if (installed_) sigaction(SIGINT, &g_chained, nullptr);
  }
  SigintScope(const SigintScope&) = delete;
  SigintScope& operator=(const SigintScope&) = delete;

 private:
  CallState* previous_target_;
  bool installed_ = false, active_ = false;
};

}  // namespace

void run(const CallOptions& opt, const std::function<void(const RunContext&)>& work) {
  // The CLI's --threads range; a negative count is no thread budget at all.
  if (opt.threads < 0 || opt.threads > kMaxThreads)
    usage_error("threads = " + std::to_string(opt.threads) + " is outside 0.." + std::to_string(kMaxThreads) +
                " (0 = all cores)");
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
  {
    std::optional<SigintScope> sigint;
    if (PyThread_get_thread_ident() == g_main_thread) sigint.emplace(st);
    py::gil_scoped_release release;
    try {
      work(ctx);
    } catch (...) {
      engine_error = std::current_exception();
    }
  }
  // The caller holds the GIL again. Ctrl-C first (the interpreter's handler
  // has scheduled KeyboardInterrupt: run it now), then the callback's own
  // exception, then the engine's error (Cancelled when the callback asked).
  // A host whose SIGINT handler is not Python's (Blender's, an embedding
  // application's) schedules no KeyboardInterrupt: raise it here, so Ctrl-C
  // gives KeyboardInterrupt in every host and Cancelled only ever means
  // "the progress callback asked".
  if (st.interrupted) {
    if (PyErr_CheckSignals() == 0) PyErr_SetNone(PyExc_KeyboardInterrupt);
    throw py::error_already_set();
  }
  if (st.callback_error) std::rethrow_exception(st.callback_error);
  if (engine_error) std::rethrow_exception(engine_error);
}

void register_call(py::module_& m) {
  g_main_thread = py::module_::import("threading").attr("main_thread")().attr("ident").cast<unsigned long>();
  (void)m;
}

}  // namespace locus::python
