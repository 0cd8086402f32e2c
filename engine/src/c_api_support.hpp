// Internals shared by the C API's source files (engine/src/c_api*.cpp): the
// session handle, the guard that turns every exception into a status and a
// per-thread message, the RunContext of one call (callbacks, threads, memory
// limit, t_factor), and the checks of the C arrays a call receives. Not installed.
//
// Every entry point runs its body inside guarded(): a locus::Error becomes its
// status (the CLI's exit status), std::bad_alloc becomes LOCUS_BAD_INPUT (a
// resource limit), anything else LOCUS_INTERNAL; nothing propagates to the C
// caller. What only C can get wrong (NULL pointers, counts that do not fit
// the arrays' index types) is checked here, before anything is allocated from
// it; what any front end can get wrong (an id out of range, a fraction, a
// time) is checked once, by the Session.
#pragma once
#include <atomic>
#include <cstdint>
#include <cstring>
#include <limits>
#include <mutex>
#include <new>
#include <string>
#include <vector>

#include "locus/error.hpp"
#include "locus/locus.h"
#include "locus/session.hpp"

struct locus_session {
  explicit locus_session(locus::Session s) : session(std::move(s)) {}
  locus::Session session;
};

// A remesh with its sites (locus_cvt_remesh, locus_cvt_run).
struct locus_remesh {
  locus::CvtResult r;
};

namespace locus::c_api_detail {

using locus::ErrorCode;
using locus::fail;

// The last error of this thread (c_api_support.cpp).
void clear_error() noexcept;
void set_error(const char* function, const char* what) noexcept;

// Upper bounds that keep every derived size within int32 indices and sane memory.
constexpr int64_t kMaxVertices = std::numeric_limits<int32_t>::max() - 1;
constexpr int64_t kMaxFaces = std::numeric_limits<int32_t>::max() / 3;
constexpr int32_t kMaxIterations = 10000;
constexpr int64_t kMaxHeatValues = int64_t(1) << 28;

locus_status status_of(int exit_status);

template <class F>
locus_status guarded(const char* function, F&& body) noexcept {
  clear_error();
  try {
    body();
    return LOCUS_OK;
  } catch (const locus::Error& e) {
    set_error(function, e.what());
    return status_of(e.exit_status());
  } catch (const std::bad_alloc&) {
    set_error(function, "out of memory");
    return LOCUS_BAD_INPUT;
  } catch (const std::exception& e) {
    try {
      set_error(function, (std::string("internal error: ") + e.what()).c_str());
    } catch (...) {
      set_error(function, "internal error");
    }
    return LOCUS_INTERNAL;
  } catch (...) {
    set_error(function, "internal error (unknown exception)");
    return LOCUS_INTERNAL;
  }
}

inline void require(bool ok, const char* message) {
  if (!ok) fail(ErrorCode::BadUsage, message);
}

// The RunContext of one call: the C callback behind a mutex (one call at a
// time, as locus.h promises), its nonzero return raising the cancel flag.
struct CallContext {
  std::atomic<bool> cancel{false};
  std::mutex mu;
  locus::RunContext ctx;
  double t_factor = 0.0;  // 0: the method's default (session.hpp's HeatQuery)
  double last_fraction = 0.0;  // the last fraction passed to the host (under mu)

  explicit CallContext(const locus_run_options* o);
  locus::HeatQuery heat() const { return locus::HeatQuery{t_factor}; }
};

locus::Session& session_of(locus_session* s);
// Error(BadUsage) unless opts->t_factor is 0: a command's options give its time (t), if it has one.
void no_run_time(const CallContext& cc);

// The frame of the entry points that return a count: -1 with the error
// `if_null` when the handle is NULL, count() otherwise (it does not throw).
template <class Count>
int64_t count_of(const char* function, const void* handle, const char* if_null, Count count) noexcept {
  clear_error();
  if (!handle) {
    set_error(function, if_null);
    return -1;
  }
  return count();
}

// The frame of an entry point on a session: the guard, the session, the
// call's context (opts checked before the body); body(session, context) does the rest.
template <class Body>
locus_status session_run(const char* function, locus_session* session, const locus_run_options* opts,
                         Body&& body) noexcept {
  return guarded(function, [&] {
    locus::Session& s = session_of(session);
    CallContext cc(opts);
    body(s, cc);
  });
}

// The output array a command cannot run without ({}: every output is optional).
struct RequiredOut {
  const void* array = nullptr;
  const char* if_null = nullptr;  // the message, naming the parameter as locus_commands.h does
};

// The frame of the locus_<command>_run that take opts->t_factor as their time
// when the options give none (geodesic, logmap): session_run with the options
// (not NULL) and the required output.
template <class Options, class Body>
locus_status timed_command_run(const char* function, locus_session* session, const Options* options,
                               RequiredOut out, const locus_run_options* opts, Body&& body) noexcept {
  return session_run(function, session, opts, [&](locus::Session& s, CallContext& cc) {
    require(options != nullptr, "options is NULL");
    if (out.if_null) require(out.array != nullptr, out.if_null);
    body(s, cc);
  });
}

// The frame of every other locus_<command>_run: their options give their time,
// if they have one, so opts->t_factor must be 0 (no_run_time).
template <class Options, class Body>
locus_status command_run(const char* function, locus_session* session, const Options* options, RequiredOut out,
                         const locus_run_options* opts, Body&& body) noexcept {
  return timed_command_run(function, session, options, out, opts, [&](locus::Session& s, CallContext& cc) {
    no_run_time(cc);
    body(s, cc);
  });
}

// Fills the caller's report, zeroed first; nothing when it is NULL (not wanted).
template <class Report, class Fill>
void report_into(Report* out, Fill fill) {
  if (!out) return;
  std::memset(out, 0, sizeof *out);
  fill(*out);
}

// A C string option: `fallback` for NULL or "" (the request's default).
std::string text(const char* s, const std::string& fallback = "");
// A C id array (NULL with 0 allowed: an empty list) as a request's ids, at most kMaxHeatValues.
std::vector<int64_t> ids(const int64_t* v, int64_t n, const char* what);
// The C API's "no value" is NaN (locus.h, as the CLI writes it).
void no_value_as_nan(double* out, int64_t n);
int32_t vertex_id(const locus::Session& s, int64_t v, const char* what);
// One C point, checked against a mesh of nv vertices and nf triangles.
locus::MeshPoint mesh_point(int64_t nv, int64_t nf, const locus_surface_point& p, const char* what, int64_t k);
std::vector<locus::MeshPoint> mesh_points(const locus::Session& s, const locus_surface_point* p, int64_t n,
                                          const char* what);
std::vector<int32_t> vertex_ids(const locus::Session& s, const int64_t* v, int64_t n, const char* what);
// NULL with 0: every vertex (an empty list for the Session).
std::vector<int32_t> optional_vertex_ids(const locus::Session& s, const int64_t* v, int64_t n, const char* what);
// Per-edge outputs of the chapter-2 pipelines into optional caller arrays.
void copy_edges(const std::vector<int32_t>& edges, const std::vector<double>& values, const std::vector<double>& xyz,
                int32_t* out_edges, double* out_values, double* out_xyz);

}  // namespace locus::c_api_detail
