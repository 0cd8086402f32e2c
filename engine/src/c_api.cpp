// The C API (engine/include/locus/locus.h) over locus::Session: versions,
// errors, the allocator, sessions and their positions. The queries are in
// c_api_geodesic.cpp, c_api_diffusion.cpp and c_api_shape.cpp; the shared
// guard and checks in c_api_support.hpp.
#include "c_api_support.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

using namespace locus::c_api_detail;

#include "field_copy.hpp"
#include "locus/core/host_allocator.hpp"
#include "locus/mesh_io.hpp"

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

// C++ helpers of the C functions around them: C++ language linkage, as they
// return C++ types.
extern "C++" {
namespace {

// The arrays of locus_session_create as a Mesh, checked as locus.h says.
locus::Mesh mesh_from_arrays(const double* xyz, int64_t nv, const int32_t* tris, int64_t nf) {
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
  m.rebuild_triangle_arrays();
  return m;
}

locus::SessionOptions session_options_of(const locus_session_options* opt) {
  locus::SessionOptions so;
  if (!opt) return so;
  if (opt->mesh_operator < LOCUS_OPERATOR_AUTO || opt->mesh_operator > LOCUS_OPERATOR_ROBUST)
    fail(ErrorCode::BadUsage, "mesh_operator = " + std::to_string(opt->mesh_operator) +
                                  " is not LOCUS_OPERATOR_AUTO, _COTAN or _ROBUST");
  so.mesh_operator = static_cast<locus::OperatorChoice>(opt->mesh_operator);
  return so;
}

}  // namespace
}  // extern "C++"

locus_status locus_session_create(const double* xyz, int64_t nv, const int32_t* tris, int64_t nf,
                                  locus_session** out) {
  return locus_session_create_ex(xyz, nv, tris, nf, nullptr, out);
}

locus_status locus_session_create_ex(const double* xyz, int64_t nv, const int32_t* tris, int64_t nf,
                                     const locus_session_options* opt, locus_session** out) {
  if (out) *out = nullptr;
  return guarded("locus_session_create", [&] {
    require(out != nullptr, "out is NULL");
    const locus::SessionOptions so = session_options_of(opt);
    *out = new locus_session(locus::Session(mesh_from_arrays(xyz, nv, tris, nf), so));
  });
}

locus_status locus_session_create_from_file_ex(const char* path, const locus_session_options* opt,
                                               locus_session** out) {
  if (out) *out = nullptr;
  return guarded("locus_session_create_from_file_ex", [&] {
    require(out != nullptr, "out is NULL");
    require(path != nullptr, "path is NULL");
    require(path[0] != '\0', "path is empty");
    const locus::SessionOptions so = session_options_of(opt);
    locus::ReadOptions ro;
    ro.weld = !(opt && opt->no_weld);
    *out = new locus_session(locus::Session::from_file(path, ro, so));
  });
}

int32_t locus_session_operator(const locus_session* session) {
  if (!session) {
    set_error("locus_session_operator", "session is NULL");
    return -1;
  }
  return session->session.operator_report().robust ? LOCUS_OPERATOR_ROBUST : LOCUS_OPERATOR_COTAN;
}

}  // extern "C"

namespace {

// What the triangle and the polygon view share: the positions and the index type.
template <class View, class CView>
View view_of(const CView& c) {
  View v;
  LOCUS_COPY_FIELDS(v, c, positions, position_stride, vertex_count);
  v.position_type = static_cast<locus::ScalarType>(c.position_type);
  v.index_type = static_cast<locus::IndexType>(c.index_type);
  return v;
}

locus::MeshView engine_view(const locus_mesh_view& c) {
  locus::MeshView v = view_of<locus::MeshView>(c);
  LOCUS_COPY_FIELDS(v, c, indices, index_stride, triangle_count);
  return v;
}

locus::PolygonMeshView engine_view(const locus_polygon_view& c) {
  locus::PolygonMeshView v = view_of<locus::PolygonMeshView>(c);
  LOCUS_COPY_FIELDS(v, c, face_offsets, face_indices, face_count);
  return v;
}

// The frame of the session constructors: *out NULL on failure, and the view checked.
template <class CView, class Make>
locus_status create_session(const char* name, const CView* view, locus_session** out, Make make) {
  if (out) *out = nullptr;
  return guarded(name, [&] {
    require(out != nullptr, "out is NULL");
    require(view != nullptr, "view is NULL");
    *out = new locus_session(make(engine_view(*view)));
  });
}

}  // namespace

extern "C" {

locus_status locus_session_create_from_view(const locus_mesh_view* view, locus_session** out) {
  return locus_session_create_from_view_ex(view, nullptr, out);
}

locus_status locus_session_create_from_view_ex(const locus_mesh_view* view, const locus_session_options* opt,
                                               locus_session** out) {
  return create_session("locus_session_create_from_view", view, out,
                        [&](const locus::MeshView& v) { return locus::Session(v, session_options_of(opt)); });
}

locus_status locus_session_create_from_polygon_view(const locus_polygon_view* view, locus_session** out) {
  return create_session("locus_session_create_from_polygon_view", view, out,
                        [](const locus::PolygonMeshView& v) { return locus::Session(v); });
}

locus_status locus_session_create_polygons(const double* xyz, int64_t nv, const int32_t* face_offsets,
                                           const int32_t* face_indices, int64_t nf, locus_session** out) {
  if (out) *out = nullptr;
  return guarded("locus_session_create_polygons", [&] {
    require(out != nullptr, "out is NULL");
    require(xyz != nullptr, "xyz is NULL");
    require(face_offsets != nullptr, "face_offsets is NULL");
    require(face_indices != nullptr, "face_indices is NULL");
    // Packed doubles and int32 ids: the view reads them as they are.
    const locus::PolygonMeshView v{.positions = xyz, .vertex_count = nv, .face_offsets = face_offsets,
                                   .face_indices = face_indices, .face_count = nf};
    *out = new locus_session(locus::Session(v));
  });
}

void locus_session_destroy(locus_session* session) {
  clear_error();
  delete session;
}

int64_t locus_session_vertex_count(const locus_session* session) {
  return count_of("locus_session_vertex_count", session, "session is NULL",
                  [&] { return session->session.num_vertices(); });
}

int64_t locus_session_face_count(const locus_session* session) {
  return count_of("locus_session_face_count", session, "session is NULL",
                  [&] { return session->session.num_faces(); });
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

}  // extern "C"
