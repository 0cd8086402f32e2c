// The C API's shared internals (c_api_support.hpp): the per-thread error
// message, the RunContext of a call, the checks of C arrays.
#include "c_api_support.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "locus/kernels/parallel/task_arenas.hpp"

namespace locus::c_api_detail {
namespace {

// The last error of this thread: the whole message, and a
// fixed buffer holding it (cut to its size) for locus_last_error_message(), so
// that the pointer handed out never dangles: only its content changes.
thread_local std::string t_last_error;
constexpr size_t kMessageBuffer = 4096;
thread_local char t_message[kMessageBuffer] = "";
constexpr const char* kUnrecorded = "locus: out of memory while recording an error";

}  // namespace

void clear_error() noexcept {
  t_last_error.clear();
  t_message[0] = '\0';
}

// Never throws: when even the message cannot be allocated, a fixed one stands in.
void set_error(const char* function, const char* what) noexcept {
  try {
    t_last_error = std::string(function) + ": " + what;
  } catch (...) {
    t_last_error.clear();
    std::strncpy(t_message, kUnrecorded, kMessageBuffer - 1);
    return;
  }
  const size_t n = std::min(t_last_error.size(), kMessageBuffer - 1);
  std::memcpy(t_message, t_last_error.data(), n);
  t_message[n] = '\0';
}

locus_status status_of(int exit_status) {
  switch (exit_status) {
    case 2: return LOCUS_BAD_USAGE;
    case 3: return LOCUS_BAD_INPUT;
    case 4: return LOCUS_NUMERICAL;
    case 5: return LOCUS_CANCELLED;
    default: return LOCUS_INTERNAL;
  }
}

CallContext::CallContext(const locus_run_options* o) {
  if (!o) return;
  if (o->threads < 0) fail(ErrorCode::BadUsage, "threads must be >= 0 (got " + std::to_string(o->threads) + ")");
  if (o->t_factor != 0.0) {  // 0: the default, so that a zero-initialized struct means all defaults
    if (!(o->t_factor > 0) || !std::isfinite(o->t_factor))
      fail(ErrorCode::BadUsage, "t_factor must be a finite positive number or 0 for the default (got " +
                                    std::to_string(o->t_factor) + ")");
    t_factor = o->t_factor;
  }
  ctx.threads = o->threads;
  if (o->message) {
    const locus_message_fn fn = o->message;
    void* const user = o->user_data;
    ctx.message = [this, fn, user](std::string_view text) {
      std::lock_guard<std::mutex> lock(mu);
      const std::string s(text);
      try {
        fn(s.c_str(), user);
      } catch (...) {  // a C++ callback that throws: the note is dropped
      }
    };
  }
  // More threads than oneTBB allows this process: clamped, and said through
  // the message callback (oneTBB would print a warning on stderr).
  if (ctx.threads > locus::max_arena_threads()) {
    const int max = locus::max_arena_threads();
    ctx.note("threads = " + std::to_string(ctx.threads) + " is more than this process allows (" +
             std::to_string(max) + "); using " + std::to_string(max));
    ctx.threads = max;
  }
  ctx.max_memory_bytes = static_cast<std::size_t>(
      std::min<uint64_t>(o->max_memory_bytes, std::numeric_limits<std::size_t>::max()));
  if (o->progress) {
    const locus_progress_fn fn = o->progress;
    void* const user = o->user_data;
    ctx.cancel = &cancel;
    ctx.progress = [this, fn, user](double fraction, std::string_view phase) {
      std::lock_guard<std::mutex> lock(mu);
      if (cancel.load()) return;
      // One monotone fraction in [0, 1] per call, whatever
      // order worker threads' reports arrive in.
      fraction = std::clamp(fraction, last_fraction, 1.0);
      last_fraction = fraction;
      const std::string name(phase);
      int stop = 1;
      try {
        stop = fn(fraction, name.c_str(), user);
      } catch (...) {  // a C++ callback that throws: treat as a request to stop
      }
      if (stop != 0) cancel.store(true);
    };
  }
}

locus::Session& session_of(locus_session* s) {
  require(s != nullptr, "session is NULL");
  return s->session;
}

// The C API's "no value" is NaN (locus.h, as the CLI writes it); the Session's
// geodesic distance in a component without a source is +infinity.
void no_value_as_nan(double* out, int64_t n) {
  for (int64_t i = 0; i < n; ++i)
    if (std::isinf(out[i])) out[i] = std::numeric_limits<double>::quiet_NaN();
}

int32_t vertex_id(const locus::Session& s, int64_t v, const char* what) {
  const int64_t n = s.num_vertices();
  if (v < 0 || v >= n)
    fail(ErrorCode::BadUsage, std::string(what) + " " + std::to_string(v) + " is not a vertex (the mesh has " +
                                  std::to_string(n) + " vertices, ids 0.." + std::to_string(n - 1) + ")");
  return static_cast<int32_t>(v);
}

// Ids out of range: BadUsage naming `what`, and [k] when k >= 0 (the name is built on failure only).
locus::MeshPoint mesh_point(int64_t nv, int64_t nf, const locus_surface_point& p, const char* what, int64_t k) {
  const auto name = [&] {
    std::string n(what);
    if (k >= 0) n.append("[").append(std::to_string(k)).append("]");
    return n;
  };
  if (p.face < 0) {
    if (p.vertex < 0 || p.vertex >= nv)
      fail(ErrorCode::BadUsage, name() + ".vertex = " + std::to_string(p.vertex) + " is not a vertex (the mesh has " +
                                    std::to_string(nv) + " vertices)");
    return locus::MeshPoint::at_vertex(static_cast<int32_t>(p.vertex));
  }
  if (p.face >= nf)
    fail(ErrorCode::BadUsage, name() + ".face = " + std::to_string(p.face) + " is not a face (the mesh has " +
                                  std::to_string(nf) + " triangles)");
  return locus::MeshPoint::in_face(static_cast<int32_t>(p.face), p.bary[0], p.bary[1], p.bary[2]);
}

std::vector<locus::MeshPoint> mesh_points(const locus::Session& s, const locus_surface_point* p, int64_t n,
                                          const char* what) {
  require(p != nullptr, (std::string(what) + " is NULL").c_str());
  if (n < 1 || n > kMaxVertices)
    fail(ErrorCode::BadUsage, std::string("the number of ") + what + " must be in 1.." + std::to_string(kMaxVertices) +
                                  " (got " + std::to_string(n) + ")");
  std::vector<locus::MeshPoint> out(static_cast<size_t>(n));
  for (int64_t k = 0; k < n; ++k)
    out[k] = mesh_point(s.num_vertices(), s.num_faces(), p[k], what, k);
  return out;
}

std::vector<int32_t> vertex_ids(const locus::Session& s, const int64_t* v, int64_t n, const char* what) {
  require(v != nullptr, (std::string(what) + " is NULL").c_str());
  if (n < 1 || n > kMaxHeatValues)
    fail(ErrorCode::BadUsage, std::string("the number of ") + what + " must be in 1..2^28 (got " + std::to_string(n) + ")");
  std::vector<int32_t> out(static_cast<size_t>(n));
  for (int64_t k = 0; k < n; ++k)
    out[k] = vertex_id(s, v[k], (std::string(what) + "[" + std::to_string(k) + "] =").c_str());
  return out;
}

// NULL with 0: every vertex (an empty list for the Session).
std::vector<int32_t> optional_vertex_ids(const locus::Session& s, const int64_t* v, int64_t n, const char* what) {
  if (v == nullptr && n == 0) return {};
  return vertex_ids(s, v, n, what);
}

// Per-edge outputs of the chapter-2 pipelines into optional caller arrays.
void copy_edges(const std::vector<int32_t>& edges, const std::vector<double>& values, const std::vector<double>& xyz,
                int32_t* out_edges, double* out_values, double* out_xyz) {
  if (out_edges) std::copy(edges.begin(), edges.end(), out_edges);
  if (out_values) std::copy(values.begin(), values.end(), out_values);
  if (out_xyz) std::copy(xyz.begin(), xyz.end(), out_xyz);
}

std::string text(const char* s, const std::string& fallback) { return s && s[0] ? std::string(s) : fallback; }

std::vector<int64_t> ids(const int64_t* v, int64_t n, const char* what) {
  if (n < 0 || n > kMaxHeatValues)
    fail(ErrorCode::BadUsage, std::string("the number of ") + what + " must be in 0..2^28 (got " +
                                  std::to_string(n) + ")");
  if (n > 0) require(v != nullptr, (std::string(what) + " is NULL").c_str());
  return n > 0 ? std::vector<int64_t>(v, v + n) : std::vector<int64_t>{};
}

void no_run_time(const CallContext& cc) {
  if (cc.t_factor != 0.0) fail(ErrorCode::BadUsage, "opts->t_factor must be 0 here: the command's options give its time (t), if it has one");
}

}  // namespace locus::c_api_detail

using namespace locus::c_api_detail;

// The last-error calls of locus.h live beside the message they read.
extern "C" {

const char* locus_last_error_message(void) { return t_message; }

int64_t locus_last_error_copy(char* buffer, int64_t capacity) {
  // The whole message, unless recording it failed (then the buffer's stand-in).
  const char* text = t_last_error.empty() ? t_message : t_last_error.c_str();
  const size_t length = t_last_error.empty() ? std::strlen(t_message) : t_last_error.size();
  if (buffer && capacity > 0) {
    const size_t n = std::min(length, static_cast<size_t>(capacity - 1));
    std::memcpy(buffer, text, n);
    buffer[n] = '\0';
  }
  return static_cast<int64_t>(length);
}

}  // extern "C"
