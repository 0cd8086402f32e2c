// The C API (engine/include/locus/locus.h) over locus::Session.
//
// Every entry point runs its body inside guarded(): a locus::Error becomes its
// status (the CLI's exit status), std::bad_alloc becomes LOCUS_BAD_INPUT (a
// resource limit), anything else LOCUS_INTERNAL; nothing propagates to the C
// caller. Arguments are checked here, before anything is allocated from them,
// because C callers cannot be trusted to pass consistent counts.
#include "locus/locus.h"

#include <algorithm>
#include <memory>
#include <atomic>
#include <cmath>
#include <cstring>
#include <limits>
#include <mutex>
#include <new>
#include <string>
#include <vector>

#include "locus/core/host_allocator.hpp"
#include "locus/error.hpp"
#include "locus/kernels/parallel/task_arenas.hpp"
#include "locus/mesh_io.hpp"
#include "locus/session.hpp"

struct locus_session {
  explicit locus_session(locus::Session s) : session(std::move(s)) {}
  locus::Session session;
};

namespace {

using locus::ErrorCode;
using locus::fail;

// The last error of this thread (issue 24 item 6): the whole message, and a
// fixed buffer holding it (cut to its size) for locus_last_error_message(), so
// that the pointer handed out never dangles: only its content changes.
thread_local std::string t_last_error;
constexpr size_t kMessageBuffer = 4096;
thread_local char t_message[kMessageBuffer] = "";
constexpr const char* kUnrecorded = "locus: out of memory while recording an error";

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

// Upper bounds that keep every derived size within int32 indices and sane memory.
constexpr int64_t kMaxVertices = std::numeric_limits<int32_t>::max() - 1;
constexpr int64_t kMaxFaces = std::numeric_limits<int32_t>::max() / 3;
constexpr int32_t kMaxIterations = 10000;
constexpr int64_t kMaxHeatValues = int64_t(1) << 28;

locus_status status_of(int exit_status) {
  switch (exit_status) {
    case 2: return LOCUS_BAD_USAGE;
    case 3: return LOCUS_BAD_INPUT;
    case 4: return LOCUS_NUMERICAL;
    case 5: return LOCUS_CANCELLED;
    default: return LOCUS_INTERNAL;
  }
}

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

void require(bool ok, const char* message) {
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

  explicit CallContext(const locus_run_options* o) {
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
    // the message callback (oneTBB would print a warning on stderr; issue 24 item 4).
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
        // One monotone fraction in [0, 1] per call (issue 24 item 3), whatever
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
  locus::HeatQuery heat() const { return locus::HeatQuery{t_factor}; }
};

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

}  // namespace

extern "C" {

locus_run_options locus_run_options_default(void) {
  locus_run_options o;
  std::memset(&o, 0, sizeof o);
  o.t_factor = 0.0;  // each method's default (locus.h)
  return o;
}

const char* locus_version(int32_t* major, int32_t* minor, int32_t* patch) {
  if (major) *major = LOCUS_VERSION_MAJOR;
  if (minor) *minor = LOCUS_VERSION_MINOR;
  if (patch) *patch = LOCUS_VERSION_PATCH;
  return LOCUS_VERSION_STRING;  // locus/version.h, generated from the CMake project version
}

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

locus_status locus_set_allocator(locus_alloc_fn alloc, locus_free_fn free_fn, void* user_data) {
  return guarded("locus_set_allocator", [&] {
    if ((alloc == nullptr) != (free_fn == nullptr))
      fail(ErrorCode::BadUsage, "alloc and free_fn must both be set or both be NULL");
    locus::set_host_allocator(alloc, free_fn, user_data);
  });
}

locus_status locus_session_create_from_file(const char* path, locus_session** out) {
  if (out) *out = nullptr;
  return guarded("locus_session_create_from_file", [&] {
    require(out != nullptr, "out is NULL");
    require(path != nullptr, "path is NULL");
    require(path[0] != '\0', "path is empty");
    *out = new locus_session(locus::Session::from_file(path));
  });
}

locus_status locus_session_create(const double* xyz, int64_t nv, const int32_t* tris, int64_t nf,
                                  locus_session** out) {
  if (out) *out = nullptr;
  return guarded("locus_session_create", [&] {
    require(out != nullptr, "out is NULL");
    require(xyz != nullptr, "xyz is NULL");
    require(tris != nullptr, "tris is NULL");
    if (nv < 1 || nv > kMaxVertices)
      fail(ErrorCode::BadUsage, "nv = " + std::to_string(nv) + " is not in 1.." + std::to_string(kMaxVertices));
    if (nf < 1 || nf > kMaxFaces)
      fail(ErrorCode::BadUsage, "nf = " + std::to_string(nf) + " is not in 1.." + std::to_string(kMaxFaces) +
                                    (nf == 0 ? " (the mesh has no faces)" : ""));
    for (int64_t i = 0; i < 3 * nv; ++i)
      if (!std::isfinite(xyz[i]))
        fail(ErrorCode::BadInput, "vertex " + std::to_string(i / 3) + " has a non-finite coordinate (" +
                                      "xyz[" + std::to_string(i) + "] = " + std::to_string(xyz[i]) + ")");
    for (int64_t k = 0; k < 3 * nf; ++k)
      if (tris[k] < 0 || tris[k] >= nv)  // an id out of range: a usage error, as locus.h says
        fail(ErrorCode::BadUsage, "triangle " + std::to_string(k / 3) + " references vertex " +
                                      std::to_string(tris[k]) + " but the mesh has " + std::to_string(nv) +
                                      " vertices (tris[" + std::to_string(k) + "])");
    locus::Mesh m;
    m.x.resize(static_cast<size_t>(nv));
    m.y.resize(static_cast<size_t>(nv));
    m.z.resize(static_cast<size_t>(nv));
    for (int64_t i = 0; i < nv; ++i) {
      m.x[i] = xyz[3 * i];
      m.y[i] = xyz[3 * i + 1];
      m.z[i] = xyz[3 * i + 2];
    }
    m.face_offsets.resize(static_cast<size_t>(nf) + 1);
    for (int64_t f = 0; f <= nf; ++f) m.face_offsets[f] = static_cast<int32_t>(3 * f);
    m.face_vertices.assign(tris, tris + 3 * nf);
    m.f0.resize(static_cast<size_t>(nf));
    m.f1.resize(static_cast<size_t>(nf));
    m.f2.resize(static_cast<size_t>(nf));
    for (int64_t f = 0; f < nf; ++f) {
      m.f0[f] = tris[3 * f];
      m.f1[f] = tris[3 * f + 1];
      m.f2[f] = tris[3 * f + 2];
    }
    *out = new locus_session(locus::Session(std::move(m)));
  });
}

locus_status locus_session_create_from_view(const locus_mesh_view* view, locus_session** out) {
  if (out) *out = nullptr;
  return guarded("locus_session_create_from_view", [&] {
    require(out != nullptr, "out is NULL");
    require(view != nullptr, "view is NULL");
    locus::MeshView v;
    v.positions = view->positions;
    v.position_type = static_cast<locus::ScalarType>(view->position_type);
    v.position_stride = view->position_stride;
    v.vertex_count = view->vertex_count;
    v.indices = view->indices;
    v.index_type = static_cast<locus::IndexType>(view->index_type);
    v.index_stride = view->index_stride;
    v.triangle_count = view->triangle_count;
    *out = new locus_session(locus::Session(v));
  });
}

locus_status locus_session_create_from_polygon_view(const locus_polygon_view* view, locus_session** out) {
  if (out) *out = nullptr;
  return guarded("locus_session_create_from_polygon_view", [&] {
    require(out != nullptr, "out is NULL");
    require(view != nullptr, "view is NULL");
    locus::PolygonMeshView v;
    v.positions = view->positions;
    v.position_type = static_cast<locus::ScalarType>(view->position_type);
    v.position_stride = view->position_stride;
    v.vertex_count = view->vertex_count;
    v.face_offsets = view->face_offsets;
    v.face_indices = view->face_indices;
    v.index_type = static_cast<locus::IndexType>(view->index_type);
    v.face_count = view->face_count;
    *out = new locus_session(locus::Session(v));
  });
}

locus_status locus_session_create_polygons(const double* xyz, int64_t nv, const int32_t* face_offsets,
                                           const int32_t* face_indices, int64_t nf, locus_session** out) {
  if (out) *out = nullptr;
  return guarded("locus_session_create_polygons", [&] {
    require(out != nullptr, "out is NULL");
    require(xyz != nullptr, "xyz is NULL");
    require(face_offsets != nullptr, "face_offsets is NULL");
    require(face_indices != nullptr, "face_indices is NULL");
    locus::PolygonMeshView v;  // packed doubles and int32 ids: the view reads them as they are
    v.positions = xyz;
    v.vertex_count = nv;
    v.face_offsets = face_offsets;
    v.face_indices = face_indices;
    v.face_count = nf;
    *out = new locus_session(locus::Session(v));
  });
}

void locus_session_destroy(locus_session* session) {
  clear_error();
  delete session;
}

int64_t locus_session_vertex_count(const locus_session* session) {
  clear_error();
  if (!session) {
    set_error("locus_session_vertex_count", "session is NULL");
    return -1;
  }
  return session->session.num_vertices();
}

int64_t locus_session_face_count(const locus_session* session) {
  clear_error();
  if (!session) {
    set_error("locus_session_face_count", "session is NULL");
    return -1;
  }
  return session->session.num_faces();
}

locus_status locus_session_get_positions(const locus_session* session, double* out_xyz) {
  return guarded("locus_session_get_positions", [&] {
    require(session != nullptr, "session is NULL");
    require(out_xyz != nullptr, "out_xyz is NULL");
    const locus::Mesh m = session->session.mesh();
    for (int32_t i = 0; i < m.num_vertices(); ++i) {
      out_xyz[3 * static_cast<size_t>(i)] = m.x[i];
      out_xyz[3 * static_cast<size_t>(i) + 1] = m.y[i];
      out_xyz[3 * static_cast<size_t>(i) + 2] = m.z[i];
    }
  });
}

locus_status locus_session_set_positions(locus_session* session, const double* xyz, int64_t nv) {
  return guarded("locus_session_set_positions", [&] {
    locus::Session& s = session_of(session);
    require(xyz != nullptr, "xyz is NULL");
    if (nv != s.num_vertices())
      fail(ErrorCode::BadUsage, "nv = " + std::to_string(nv) + " but the session has " +
                                    std::to_string(s.num_vertices()) + " vertices");
    s.set_positions(std::span<const double>(xyz, 3 * static_cast<size_t>(nv)));
  });
}

locus_status locus_geodesic_distance_ex(locus_session* session, int64_t source, double* out_nv,
                                        const locus_run_options* opts) {
  return guarded("locus_geodesic_distance", [&] {
    locus::Session& s = session_of(session);
    require(out_nv != nullptr, "out_nv is NULL");
    const int32_t src = vertex_id(s, source, "source");
    CallContext cc(opts);
    s.geodesic_distance(src, std::span<double>(out_nv, static_cast<size_t>(s.num_vertices())), cc.heat(), cc.ctx);
    no_value_as_nan(out_nv, s.num_vertices());
  });
}

locus_status locus_geodesic_distance(locus_session* session, int64_t source, double* out_nv) {
  return locus_geodesic_distance_ex(session, source, out_nv, nullptr);
}

locus_status locus_logmap_ex(locus_session* session, int64_t center, double fraction, double* out_uv,
                             const locus_run_options* opts) {
  return guarded("locus_logmap", [&] {
    locus::Session& s = session_of(session);
    require(out_uv != nullptr, "out_uv is NULL");
    const int32_t c = vertex_id(s, center, "center");
    if (!(fraction > 0 && fraction <= 1))
      fail(ErrorCode::BadUsage, "fraction must be in (0, 1] (got " + std::to_string(fraction) + ")");
    CallContext cc(opts);
    const locus::LogMapResult r = s.logmap(c, fraction, cc.heat(), cc.ctx);
    const size_t n = static_cast<size_t>(s.num_vertices());
    std::fill(out_uv, out_uv + 2 * n, std::numeric_limits<double>::quiet_NaN());
    for (size_t k = 0; k < r.patch.size(); ++k) {
      out_uv[2 * static_cast<size_t>(r.patch[k])] = r.u[k];
      out_uv[2 * static_cast<size_t>(r.patch[k]) + 1] = r.v[k];
    }
  });
}

int64_t locus_valid_mask(const double* values, int64_t count, int64_t stride, int32_t* out_valid) {
  clear_error();
  if (!values || !out_valid || count < 0 || stride < 1) {
    set_error("locus_valid_mask", !values      ? "values is NULL"
                                  : !out_valid ? "out_valid is NULL"
                                  : count < 0  ? "count < 0"
                                               : "stride < 1");
    return -1;
  }
  int64_t valid = 0;
  for (int64_t i = 0; i < count; ++i) {
    out_valid[i] = std::isnan(values[i * stride]) ? 0 : 1;
    valid += out_valid[i];
  }
  return valid;
}

locus_status locus_logmap(locus_session* session, int64_t center, double fraction, double* out_uv) {
  return locus_logmap_ex(session, center, fraction, out_uv, nullptr);
}

locus_status locus_cvt_ex(locus_session* session, int32_t sites, int32_t iters, uint64_t seed,
                          int32_t* out_labels_nv, double* out_sites_xyz, const locus_run_options* opts) {
  return guarded("locus_cvt", [&] {
    locus::Session& s = session_of(session);
    require(out_labels_nv != nullptr, "out_labels_nv is NULL");
    if (sites < 1 || sites > s.num_vertices())
      fail(ErrorCode::BadUsage, "sites = " + std::to_string(sites) + " is not in 1.." +
                                    std::to_string(s.num_vertices()) + " (the vertex count)");
    if (iters < 0 || iters > kMaxIterations)
      fail(ErrorCode::BadUsage, "iters = " + std::to_string(iters) + " is not in 0.." + std::to_string(kMaxIterations));
    CallContext cc(opts);
    if (cc.t_factor != 0.0)
      fail(ErrorCode::BadUsage, "t_factor: cvt uses its own default t = 4h^2; leave t_factor at 0 (default)");
    const locus::CvtResult r = s.cvt(sites, iters, seed, cc.ctx);
    std::copy(r.label.begin(), r.label.end(), out_labels_nv);
    if (out_sites_xyz) std::copy(r.site_xyz.begin(), r.site_xyz.end(), out_sites_xyz);
  });
}

locus_status locus_cvt(locus_session* session, int32_t sites, int32_t iters, uint64_t seed, int32_t* out_labels_nv) {
  return locus_cvt_ex(session, sites, iters, seed, out_labels_nv, nullptr, nullptr);
}

}  // extern "C"

struct locus_remesh {
  locus::CvtResult r;
};

extern "C" {

locus_status locus_cvt_remesh(locus_session* session, int32_t sites, int32_t iters, uint64_t seed,
                              const locus_run_options* opts, locus_remesh** out) {
  return guarded("locus_cvt_remesh", [&] {
    locus::Session& s = session_of(session);
    require(out != nullptr, "out is NULL");
    if (sites < 1 || sites > s.num_vertices())
      fail(ErrorCode::BadUsage, "sites = " + std::to_string(sites) + " is not in 1.." +
                                    std::to_string(s.num_vertices()) + " (the vertex count)");
    if (iters < 0 || iters > kMaxIterations)
      fail(ErrorCode::BadUsage, "iters = " + std::to_string(iters) + " is not in 0.." + std::to_string(kMaxIterations));
    CallContext cc(opts);
    if (cc.t_factor != 0.0)
      fail(ErrorCode::BadUsage, "t_factor: cvt uses its own default t = 4h^2; leave t_factor at 0 (default)");
    auto h = std::make_unique<locus_remesh>();
    h->r = s.cvt(sites, iters, seed, cc.ctx, true);
    if (!h->r.remeshed)
      fail(ErrorCode::Numerical, "the cells still break the closed-ball property after the repair rounds; "
                                 "no manifold remesh (try more sites)");
    *out = h.release();
  });
}

locus_status locus_remesh_get(const locus_remesh* remesh, double* out_xyz, int32_t* out_tris) {
  return guarded("locus_remesh_get", [&] {
    require(remesh != nullptr, "remesh is NULL");
    if (out_xyz) std::copy(remesh->r.remesh_xyz.begin(), remesh->r.remesh_xyz.end(), out_xyz);
    if (out_tris) std::copy(remesh->r.remesh_triangles.begin(), remesh->r.remesh_triangles.end(), out_tris);
  });
}

locus_status locus_remesh_get_stats(const locus_remesh* remesh, locus_remesh_stats* out) {
  return guarded("locus_remesh_get_stats", [&] {
    require(remesh != nullptr, "remesh is NULL");
    require(out != nullptr, "out is NULL");
    const locus::CvtResult& r = remesh->r;
    *out = locus_remesh_stats{};
    out->vertices = static_cast<int64_t>(r.remesh_xyz.size() / 3);
    out->faces = static_cast<int64_t>(r.remesh_triangles.size() / 3);
    out->manifold = r.remeshed ? 1 : 0;
    out->genus = r.remesh_genus;
    out->components = r.remesh_components;
    out->boundary_loops = r.remesh_boundary_loops;
    out->mean_min_angle_deg = r.mean_min_angle_deg;
    out->min_angle_deg = r.min_angle_deg;
    out->pct_below_30_deg = r.pct_below_30_deg;
    out->hausdorff_rel = r.hausdorff_rel;
    out->added_sites = r.added_sites;
  });
}

void locus_remesh_destroy(locus_remesh* remesh) { delete remesh; }

locus_status locus_heat_values(locus_session* session, const int64_t* sources, int64_t n_sources,
                               const int64_t* targets, int64_t n_targets, double* out,
                               const locus_run_options* opts) {
  return guarded("locus_heat_values", [&] {
    locus::Session& s = session_of(session);
    require(sources != nullptr, "sources is NULL");
    require(targets != nullptr, "targets is NULL");
    require(out != nullptr, "out is NULL");
    if (n_sources < 1 || n_targets < 1 || n_sources > kMaxHeatValues || n_targets > kMaxHeatValues ||
        n_sources * n_targets > kMaxHeatValues)
      fail(ErrorCode::BadUsage, "n_sources = " + std::to_string(n_sources) + ", n_targets = " +
                                    std::to_string(n_targets) + ": each must be >= 1 and their product <= 2^28");
    std::vector<int32_t> src(static_cast<size_t>(n_sources)), tgt(static_cast<size_t>(n_targets));
    for (int64_t k = 0; k < n_sources; ++k)
      src[k] = vertex_id(s, sources[k], ("sources[" + std::to_string(k) + "] =").c_str());
    for (int64_t k = 0; k < n_targets; ++k)
      tgt[k] = vertex_id(s, targets[k], ("targets[" + std::to_string(k) + "] =").c_str());
    CallContext cc(opts);
    const std::vector<double> v = s.heat_values(src, tgt, cc.heat(), cc.ctx);
    std::copy(v.begin(), v.end(), out);
  });
}

}  // extern "C"

// ==== Pipelines added by issue 24 (locus.h, same order). ====

namespace {

// One C point, checked against a mesh of nv vertices and nf triangles (ids out of
// range: BadUsage naming `what`, and [k] when k >= 0; the name is built on failure only).
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

}  // namespace

struct locus_nncoords_field {
  explicit locus_nncoords_field(locus::NaturalNeighbors f, int32_t nv, int32_t nf) : field(std::move(f)), nv(nv), nf(nf) {}
  locus::NaturalNeighbors field;
  int32_t nv, nf;
};

extern "C" {

locus_status locus_session_prepare(locus_session* session, int32_t operators, const locus_run_options* opts) {
  return guarded("locus_session_prepare", [&] {
    locus::Session& s = session_of(session);
    const int32_t all = LOCUS_PREPARE_HEAT_METHOD | LOCUS_PREPARE_DIFFUSION | LOCUS_PREPARE_LAPLACIAN;
    if (operators & ~all)
      fail(ErrorCode::BadUsage, "operators = " + std::to_string(operators) + " has bits outside LOCUS_PREPARE_*");
    CallContext cc(opts);
    if (operators & LOCUS_PREPARE_HEAT_METHOD) s.prepare_heat(cc.heat(), cc.ctx);
    if (operators & LOCUS_PREPARE_DIFFUSION) s.prepare_diffusion(cc.heat(), cc.ctx);
    if (operators & LOCUS_PREPARE_LAPLACIAN) s.prepare_patch_parameterization(cc.ctx);
  });
}

locus_status locus_random_surface_points(const locus_session* session, int64_t count, uint64_t seed,
                                         locus_surface_point* out) {
  return guarded("locus_random_surface_points", [&] {
    require(session != nullptr, "session is NULL");
    require(out != nullptr, "out is NULL");
    if (count < 0 || count > kMaxVertices)
      fail(ErrorCode::BadUsage, "count = " + std::to_string(count) + " is not in 0.." + std::to_string(kMaxVertices));
    const std::vector<locus::MeshPoint> p = session->session.random_points(static_cast<int32_t>(count), seed);
    for (size_t k = 0; k < p.size(); ++k) out[k] = locus_surface_point{p[k].face, -1, {p[k].bary[0], p[k].bary[1], p[k].bary[2]}};
  });
}

locus_status locus_geodesic_distance_multi(locus_session* session, const locus_surface_point* sources,
                                           int64_t n_sources, double* out_nv, const locus_run_options* opts) {
  return guarded("locus_geodesic_distance_multi", [&] {
    locus::Session& s = session_of(session);
    require(out_nv != nullptr, "out_nv is NULL");
    const std::vector<locus::MeshPoint> pts = mesh_points(s, sources, n_sources, "sources");
    CallContext cc(opts);
    s.geodesic_distance(pts, std::span<double>(out_nv, static_cast<size_t>(s.num_vertices())), cc.heat(), cc.ctx);
    no_value_as_nan(out_nv, s.num_vertices());
  });
}

locus_status locus_voronoi_bound(const locus_session* session, int64_t* max_points, int64_t* max_lines,
                                 int64_t* max_line_points) {
  return guarded("locus_voronoi_bound", [&] {
    require(session != nullptr, "session is NULL");
    const int64_t nf = session->session.num_faces();
    // An edge point per mesh edge (<= 3 nf) plus a corner per face; <= 3 segments per face,
    // and a polyline of k segments has k + 1 points.
    if (max_points) *max_points = 4 * nf;
    if (max_lines) *max_lines = 3 * nf;
    if (max_line_points) *max_line_points = 6 * nf;
  });
}

locus_status locus_voronoi(locus_session* session, const locus_surface_point* generators, int64_t n_generators,
                           locus_voronoi_output* out, const locus_run_options* opts) {
  return guarded("locus_voronoi", [&] {
    locus::Session& s = session_of(session);
    require(out != nullptr, "out is NULL");
    const std::vector<locus::MeshPoint> g = mesh_points(s, generators, n_generators, "generators");
    CallContext cc(opts);
    const locus::VoronoiResult r = s.voronoi(g, cc.heat(), cc.ctx);
    out->n_points = static_cast<int64_t>(r.points.size() / 3);
    out->n_lines = static_cast<int64_t>(r.line_offsets.size()) - 1;
    out->n_line_points = static_cast<int64_t>(r.line_points.size());
    if (out->labels) std::copy(r.label.begin(), r.label.end(), out->labels);
    const auto check = [](const void* p, int64_t capacity, int64_t need, const char* what) {
      if (p && capacity < need)
        fail(ErrorCode::BadUsage, std::string(what) + " holds " + std::to_string(capacity) + " but the diagram has " +
                                      std::to_string(need) + " (locus_voronoi_bound gives capacities that suffice)");
    };
    check(out->points, out->points_capacity, out->n_points, "points_capacity");
    check(out->line_offsets, out->lines_capacity, out->n_lines, "lines_capacity");
    check(out->line_points, out->line_points_capacity, out->n_line_points, "line_points_capacity");
    if (out->points) std::copy(r.points.begin(), r.points.end(), out->points);
    if (out->line_offsets) std::copy(r.line_offsets.begin(), r.line_offsets.end(), out->line_offsets);
    if (out->line_points) std::copy(r.line_points.begin(), r.line_points.end(), out->line_points);
  });
}

locus_status locus_nncoords_prepare(locus_session* session, const locus_surface_point* sites, int64_t n_sites,
                                    const locus_run_options* opts, locus_nncoords_field** out) {
  if (out) *out = nullptr;
  return guarded("locus_nncoords_prepare", [&] {
    locus::Session& s = session_of(session);
    require(out != nullptr, "out is NULL");
    const std::vector<locus::MeshPoint> p = mesh_points(s, sites, n_sites, "sites");
    CallContext cc(opts);
    *out = new locus_nncoords_field(s.prepare_natural_neighbors(p, cc.heat(), cc.ctx), s.num_vertices(), s.num_faces());
  });
}

locus_status locus_nncoords_query(const locus_nncoords_field* nn, const locus_surface_point* point, double* out_weights) {
  return guarded("locus_nncoords_query", [&] {
    require(nn != nullptr, "nn is NULL");
    require(point != nullptr, "point is NULL");
    require(out_weights != nullptr, "out_weights is NULL");
    const locus::MeshPoint q = mesh_point(nn->nv, nn->nf, *point, "point", -1);
    const locus::NaturalNeighborResult r = nn->field.coordinates(q);
    std::copy(r.weight.begin(), r.weight.end(), out_weights);
  });
}

int64_t locus_nncoords_site_count(const locus_nncoords_field* nn) {
  clear_error();
  if (!nn) {
    set_error("locus_nncoords_site_count", "nn is NULL");
    return -1;
  }
  return nn->field.num_sites();
}

void locus_nncoords_destroy(locus_nncoords_field* nn) {
  clear_error();
  delete nn;
}

locus_status locus_nncoords(locus_session* session, const locus_surface_point* sites, int64_t n_sites,
                            const locus_surface_point* point, double* out_weights, const locus_run_options* opts) {
  return guarded("locus_nncoords", [&] {
    locus::Session& s = session_of(session);
    require(out_weights != nullptr, "out_weights is NULL");
    const std::vector<locus::MeshPoint> q = mesh_points(s, point, 1, "point");  // before the diagram: fails fast
    const std::vector<locus::MeshPoint> p = mesh_points(s, sites, n_sites, "sites");
    CallContext cc(opts);
    const locus::NaturalNeighborResult r = s.natural_neighbor_coordinates(p, q[0], cc.heat(), cc.ctx);
    std::copy(r.weight.begin(), r.weight.end(), out_weights);
  });
}

locus_status locus_skinning_weights(locus_session* session, const locus_surface_point* handles, int64_t n_handles,
                                    double* out, const locus_run_options* opts) {
  return guarded("locus_skinning_weights", [&] {
    locus::Session& s = session_of(session);
    require(out != nullptr, "out is NULL");
    const std::vector<locus::MeshPoint> h = mesh_points(s, handles, n_handles, "handles");
    CallContext cc(opts);
    const locus::SkinningWeightsResult r = s.skinning_weights(h, cc.heat(), cc.ctx);
    std::copy(r.weight.begin(), r.weight.end(), out);
  });
}

locus_status locus_adf(locus_session* session, const int64_t* vertices, int64_t n_vertices, int32_t selected_inversion,
                       double* out, const locus_run_options* opts) {
  return guarded("locus_adf", [&] {
    locus::Session& s = session_of(session);
    require(out != nullptr, "out is NULL");
    const std::vector<int32_t> v = optional_vertex_ids(s, vertices, n_vertices, "vertices");
    CallContext cc(opts);
    const std::vector<double> r = s.auto_diffusion(
        v, cc.heat(), selected_inversion ? locus::DiagonalMethod::SelectedInversion : locus::DiagonalMethod::Subset,
        cc.ctx);
    std::copy(r.begin(), r.end(), out);
  });
}

locus_status locus_hks(locus_session* session, const double* t_factors, int64_t n_times, const int64_t* vertices,
                       int64_t n_vertices, int32_t selected_inversion, double* out, const locus_run_options* opts) {
  return guarded("locus_hks", [&] {
    locus::Session& s = session_of(session);
    require(out != nullptr, "out is NULL");
    require(t_factors != nullptr, "t_factors is NULL");
    if (n_times < 1 || n_times > 1000)
      fail(ErrorCode::BadUsage, "n_times = " + std::to_string(n_times) + " is not in 1..1000");
    std::vector<locus::HeatQuery> times;
    for (int64_t j = 0; j < n_times; ++j) {
      if (!(t_factors[j] > 0) || !std::isfinite(t_factors[j]))
        fail(ErrorCode::BadUsage, "t_factors[" + std::to_string(j) + "] = " + std::to_string(t_factors[j]) +
                                      " is not a finite positive number");
      times.push_back(locus::HeatQuery{t_factors[j], 0.0});
    }
    const std::vector<int32_t> v = optional_vertex_ids(s, vertices, n_vertices, "vertices");
    CallContext cc(opts);
    const std::vector<double> r = s.heat_kernel_signature(
        times, v, selected_inversion ? locus::DiagonalMethod::SelectedInversion : locus::DiagonalMethod::Subset,
        cc.ctx);
    std::copy(r.begin(), r.end(), out);
  });
}

locus_status locus_heat_exchange(locus_session* session, const int64_t* sources, int64_t n_sources,
                                 const int64_t* targets, int64_t n_targets, double* out_targets,
                                 const locus_run_options* opts) {
  return guarded("locus_heat_exchange", [&] {
    locus::Session& s = session_of(session);
    require(out_targets != nullptr, "out_targets is NULL");
    const std::vector<int32_t> src = vertex_ids(s, sources, n_sources, "sources");
    const std::vector<int32_t> tgt = vertex_ids(s, targets, n_targets, "targets");
    CallContext cc(opts);
    const std::vector<double> r = s.heat_exchange(src, tgt, cc.heat(), cc.ctx);
    std::copy(r.begin(), r.end(), out_targets);
  });
}

locus_status locus_deform(locus_session* session, const locus_deform_request* request, double* out_xyz,
                          const locus_run_options* opts) {
  return guarded("locus_deform", [&] {
    locus::Session& s = session_of(session);
    require(request != nullptr, "request is NULL");
    require(out_xyz != nullptr, "out_xyz is NULL");
    locus::DeformRequest r;
    r.roi_seed = vertex_id(s, request->roi_seed, "request->roi_seed");
    r.handle_vertex = vertex_id(s, request->handle_vertex, "request->handle_vertex");
    r.roi_fraction = request->roi_fraction;
    r.handle_ring = request->handle_ring;
    r.offset = {request->offset[0], request->offset[1], request->offset[2]};
    r.energy = request->bilaplacian ? locus::DeformEnergyKind::Bilaplacian : locus::DeformEnergyKind::Laplacian;
    CallContext cc(opts);
    const locus::DeformResult d = s.deform(r, cc.ctx);
    std::copy(d.xyz.begin(), d.xyz.end(), out_xyz);
  });
}

locus_status locus_param_disk(locus_session* session, int32_t method, int32_t max_iterations, double eps,
                              double* out_uv, int64_t* out_flipped, const locus_run_options* opts) {
  return guarded("locus_param_disk", [&] {
    locus::Session& s = session_of(session);
    require(out_uv != nullptr, "out_uv is NULL");
    if (method < 0 || method > 2)
      fail(ErrorCode::BadUsage, "method = " + std::to_string(method) + " is not 0 (perfect), 1 (cotan) or 2 (uniform)");
    locus::DiskParamRequest r;
    r.method = method == 1 ? locus::DiskParamMethod::Cotan
               : method == 2 ? locus::DiskParamMethod::Uniform : locus::DiskParamMethod::Perfect;
    r.max_iterations = max_iterations;
    r.eps = eps;
    CallContext cc(opts);
    const locus::DiskParamResult p = s.parameterize_disk(r, cc.ctx);
    std::copy(p.uv.begin(), p.uv.end(), out_uv);
    if (out_flipped) *out_flipped = p.flipped_faces;
  });
}

locus_status locus_param_patch(locus_session* session, int64_t center, double fraction, int32_t boundary,
                               double* out_uv, int64_t* out_patch_size, int64_t* out_flipped,
                               const locus_run_options* opts) {
  return guarded("locus_param_patch", [&] {
    locus::Session& s = session_of(session);
    require(out_uv != nullptr, "out_uv is NULL");
    if (boundary != 0 && boundary != 1)
      fail(ErrorCode::BadUsage, "boundary = " + std::to_string(boundary) + " is not 0 (Neumann) or 1 (circle)");
    locus::PatchParamRequest r;
    r.center = vertex_id(s, center, "center");
    r.fraction = fraction;
    r.boundary = boundary == 1 ? locus::PatchBoundary::Circle : locus::PatchBoundary::Neumann;
    CallContext cc(opts);
    const locus::PatchParamResult p = s.parameterize_patch(r, cc.ctx);
    const size_t n = static_cast<size_t>(s.num_vertices());
    std::fill(out_uv, out_uv + 2 * n, std::numeric_limits<double>::quiet_NaN());
    for (size_t k = 0; k < p.vertices.size(); ++k) {
      out_uv[2 * static_cast<size_t>(p.vertices[k])] = p.uv[2 * k];
      out_uv[2 * static_cast<size_t>(p.vertices[k]) + 1] = p.uv[2 * k + 1];
    }
    if (out_patch_size) *out_patch_size = static_cast<int64_t>(p.vertices.size());
    if (out_flipped) *out_flipped = p.flipped_faces;
  });
}

int64_t locus_session_edge_count(const locus_session* session) {
  clear_error();
  if (!session) {
    set_error("locus_session_edge_count", "session is NULL");
    return -1;
  }
  return session->session.num_edges();
}

locus_status locus_perfect_laplacian(locus_session* session, int32_t planar, int32_t max_iterations, double eps,
                                     int32_t* out_edges, double* out_weights, double* out_xyz,
                                     int32_t* out_converged, const locus_run_options* opts) {
  return guarded("locus_perfect_laplacian", [&] {
    locus::Session& s = session_of(session);
    locus::PerfectLaplacianRequest r;
    r.planar = planar != 0;
    r.max_iterations = max_iterations;
    r.eps = eps;
    CallContext cc(opts);
    const locus::PerfectLaplacianOutput p = s.perfect_laplacian(r, cc.ctx);
    copy_edges(p.edges, p.weights, p.xyz, out_edges, out_weights, out_xyz);
    if (out_converged) *out_converged = p.converged ? 1 : 0;
  });
}

locus_status locus_self_supporting(locus_session* session, double load_density, int32_t max_iterations, double eps,
                                   int32_t* out_edges, double* out_forces, double* out_xyz, int32_t* out_converged,
                                   const locus_run_options* opts) {
  return guarded("locus_self_supporting", [&] {
    locus::Session& s = session_of(session);
    locus::SelfSupportRequest r;
    r.load_density = load_density;
    r.max_iterations = max_iterations;
    r.eps = eps;
    CallContext cc(opts);
    const locus::SelfSupportOutput p = s.self_supporting(r, cc.ctx);
    copy_edges(p.edges, p.forces, p.xyz, out_edges, out_forces, out_xyz);
    if (out_converged) *out_converged = p.converged ? 1 : 0;
  });
}

}  // extern "C"
