// Reading a MeshView into a Mesh (core/include/locus/mesh_view.hpp; README "Embedding").
#include "locus/mesh_view.hpp"

#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include "locus/error.hpp"

namespace locus {

namespace {

int64_t scalar_size(ScalarType t) {
  switch (t) {
    case ScalarType::Float32: return 4;
    case ScalarType::Float64: return 8;
  }
  fail(ErrorCode::BadUsage, "mesh view: unknown position type " + std::to_string(static_cast<int32_t>(t)));
}

int64_t index_size(IndexType t) {
  switch (t) {
    case IndexType::UInt16: return 2;
    case IndexType::UInt32: return 4;
    case IndexType::Int32: return 4;
  }
  fail(ErrorCode::BadUsage, "mesh view: unknown index type " + std::to_string(static_cast<int32_t>(t)));
}

// Host buffers need not be aligned: every element is read through memcpy.
template <class T>
T load(const char* p) {
  T v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

double read_scalar(const char* p, ScalarType t) {
  return t == ScalarType::Float32 ? static_cast<double>(load<float>(p)) : load<double>(p);
}

int64_t read_index(const char* p, IndexType t) {
  switch (t) {
    case IndexType::UInt16: return load<uint16_t>(p);
    case IndexType::UInt32: return load<uint32_t>(p);
    default: return load<int32_t>(p);
  }
}

constexpr int64_t kMaxVertices = std::numeric_limits<int32_t>::max() - 1;

// The positions of either view into m.x, m.y, m.z.
void read_positions(const void* positions, ScalarType type, int64_t stride, int64_t count, const char* what, Mesh& m) {
  if (!positions) fail(ErrorCode::BadUsage, std::string(what) + ": positions is NULL");
  if (count < 1 || count > kMaxVertices)
    fail(ErrorCode::BadUsage, std::string(what) + ": vertex_count = " + std::to_string(count) + " is not in 1.." +
                                  std::to_string(kMaxVertices));
  const int64_t ps = scalar_size(type);
  const int64_t pstride = stride == 0 ? 3 * ps : stride;
  if (pstride < 3 * ps)
    fail(ErrorCode::BadUsage, std::string(what) + ": position_stride = " + std::to_string(stride) +
                                  " bytes is shorter than a vertex (" + std::to_string(3 * ps) + " bytes)");
  m.x.resize(static_cast<size_t>(count));
  m.y.resize(static_cast<size_t>(count));
  m.z.resize(static_cast<size_t>(count));
  const char* pos = static_cast<const char*>(positions);
  for (int64_t i = 0; i < count; ++i) {
    const char* p = pos + i * pstride;
    const double x = read_scalar(p, type), y = read_scalar(p + ps, type), z = read_scalar(p + 2 * ps, type);
    if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z))
      fail(ErrorCode::BadInput, std::string(what) + ": vertex " + std::to_string(i) + " has a non-finite coordinate");
    m.x[i] = x;
    m.y[i] = y;
    m.z[i] = z;
  }
}

}  // namespace

Mesh mesh_from_view(const MeshView& v) {
  constexpr int64_t kMaxTriangles = std::numeric_limits<int32_t>::max() / 3;
  if (!v.positions) fail(ErrorCode::BadUsage, "mesh view: positions is NULL");
  if (!v.indices) fail(ErrorCode::BadUsage, "mesh view: indices is NULL");
  if (v.vertex_count < 1 || v.vertex_count > kMaxVertices)
    fail(ErrorCode::BadUsage, "mesh view: vertex_count = " + std::to_string(v.vertex_count) + " is not in 1.." +
                                  std::to_string(kMaxVertices));
  if (v.triangle_count < 1 || v.triangle_count > kMaxTriangles)
    fail(ErrorCode::BadUsage, "mesh view: triangle_count = " + std::to_string(v.triangle_count) + " is not in 1.." +
                                  std::to_string(kMaxTriangles));
  const int64_t is = index_size(v.index_type);
  const int64_t istride = v.index_stride == 0 ? 3 * is : v.index_stride;
  if (istride < 3 * is)
    fail(ErrorCode::BadUsage, "mesh view: index_stride = " + std::to_string(v.index_stride) +
                                  " bytes is shorter than a triangle (" + std::to_string(3 * is) + " bytes)");
  const int64_t nv = v.vertex_count, nf = v.triangle_count;
  Mesh m;
  read_positions(v.positions, v.position_type, v.position_stride, nv, "mesh view", m);
  m.face_offsets.resize(static_cast<size_t>(nf) + 1);
  m.face_vertices.resize(static_cast<size_t>(3 * nf));
  const char* idx = static_cast<const char*>(v.indices);
  for (int64_t f = 0; f < nf; ++f) {
    m.face_offsets[f] = static_cast<int32_t>(3 * f);
    for (int k = 0; k < 3; ++k) {
      const int64_t id = read_index(idx + f * istride + k * is, v.index_type);
      if (id < 0 || id >= nv)
        fail(ErrorCode::BadUsage, "mesh view: triangle " + std::to_string(f) + " references vertex " +
                                      std::to_string(id) + " but the view has " + std::to_string(nv) + " vertices",
             ErrorLocation{id, -1});
      m.face_vertices[3 * f + k] = static_cast<int32_t>(id);
    }
  }
  m.face_offsets[nf] = static_cast<int32_t>(3 * nf);
  m.rebuild_triangle_arrays();
  return m;
}

Mesh mesh_from_view(const PolygonMeshView& v) {
  constexpr int64_t kMaxCorners = std::numeric_limits<int32_t>::max();
  if (!v.face_offsets) fail(ErrorCode::BadUsage, "polygon view: face_offsets is NULL");
  if (!v.face_indices) fail(ErrorCode::BadUsage, "polygon view: face_indices is NULL");
  if (v.face_count < 1 || v.face_count > kMaxCorners / 3)
    fail(ErrorCode::BadUsage, "polygon view: face_count = " + std::to_string(v.face_count) + " is not in 1.." +
                                  std::to_string(kMaxCorners / 3));
  const int64_t is = index_size(v.index_type), nf = v.face_count;
  Mesh m;
  read_positions(v.positions, v.position_type, v.position_stride, v.vertex_count, "polygon view", m);
  const char* off = static_cast<const char*>(v.face_offsets);
  const char* idx = static_cast<const char*>(v.face_indices);
  if (read_index(off, v.index_type) != 0)
    fail(ErrorCode::BadUsage, "polygon view: face_offsets[0] = " + std::to_string(read_index(off, v.index_type)) +
                                  ", must be 0");
  m.face_offsets.assign(1, 0);
  for (int64_t f = 0; f < nf; ++f) {
    const int64_t b = read_index(off + f * is, v.index_type), e = read_index(off + (f + 1) * is, v.index_type);
    if (e - b < 3)  // also offsets that decrease: the face's content is wrong, as a triangle's bad id
      fail(ErrorCode::BadInput, "polygon view: face " + std::to_string(f) + " has " + std::to_string(e - b) +
                                    " corners (face_offsets[" + std::to_string(f) + ".." + std::to_string(f + 1) +
                                    "] = " + std::to_string(b) + ", " + std::to_string(e) + "); at least 3 needed");
    if (e > kMaxCorners)
      fail(ErrorCode::BadUsage, "polygon view: face_offsets[" + std::to_string(f + 1) + "] = " + std::to_string(e) +
                                    " is beyond the 2^31-1 corners a mesh can hold");
    for (int64_t k = b; k < e; ++k) {
      const int64_t id = read_index(idx + k * is, v.index_type);
      if (id < 0 || id >= v.vertex_count)
        fail(ErrorCode::BadUsage, "polygon view: face " + std::to_string(f) + " references vertex " +
                                      std::to_string(id) + " but the view has " + std::to_string(v.vertex_count) +
                                      " vertices (face_indices[" + std::to_string(k) + "])",
             ErrorLocation{id, -1});
      m.face_vertices.push_back(static_cast<int32_t>(id));
    }
    m.face_offsets.push_back(static_cast<int32_t>(e));
  }
  m.rebuild_triangle_arrays();
  return m;
}

}  // namespace locus
