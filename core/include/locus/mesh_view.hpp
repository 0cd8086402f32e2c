// locus::MeshView — a triangle mesh in the host's own buffers.
//
// Game engines and DCC tools keep float positions in interleaved vertex
// buffers and uint16/uint32 indices. A MeshView describes such buffers
// without converting them first: positions as float or double at a byte
// stride, triangles as uint16, uint32 or int32 ids at a byte stride.
// mesh_from_view() reads them once into a locus::Mesh (doubles, int32 ids):
// that is the one internal copy a Session makes (Session(const MeshView&)).
// float -> double and uint16/uint32 -> int32 are exact, so a view of float
// positions gives bit-identical results to double input holding the same values.
#pragma once
#include <cstdint>

#include "locus/export.h"
#include "locus/mesh.hpp"

LOCUS_API_BEGIN
namespace locus {

enum class ScalarType : int32_t { Float32 = 1, Float64 = 2 };
enum class IndexType : int32_t { UInt16 = 1, UInt32 = 2, Int32 = 3 };

struct LOCUS_API MeshView {
  // Vertex i's x, y, z: three consecutive values of position_type starting at
  // (const char*)positions + i * position_stride. Stride 0 = tightly packed.
  const void* positions = nullptr;
  ScalarType position_type = ScalarType::Float64;
  int64_t position_stride = 0;  // bytes; 0 or >= 3 * sizeof(scalar)
  int64_t vertex_count = 0;
  // Triangle f's three vertex ids: consecutive values of index_type starting at
  // (const char*)indices + f * index_stride. Stride 0 = tightly packed.
  const void* indices = nullptr;
  IndexType index_type = IndexType::Int32;
  int64_t index_stride = 0;  // bytes; 0 or >= 3 * sizeof(index)
  int64_t triangle_count = 0;
};

// Reads the view into a Mesh (no alignment needed). Error(BadUsage) for a NULL
// buffer, a count out of 1..2^31-2 (triangles 1..(2^31-1)/3), a stride shorter
// than its element, an unknown type or a vertex id out of range (naming the
// triangle); Error(BadInput) for a non-finite coordinate (naming the vertex).
// Topology (manifold, degenerate faces) is checked by the Session, as for files.
LOCUS_API Mesh mesh_from_view(const MeshView& view);

// A polygon mesh (quads, mixed, n-gons) in the host's buffers:
// positions as in MeshView; faces in CSR form, both arrays of index_type,
// packed: face f's corners are face_indices[face_offsets[f] .. face_offsets[f + 1]),
// face_offsets has face_count + 1 entries and starts at 0.
struct LOCUS_API PolygonMeshView {
  const void* positions = nullptr;
  ScalarType position_type = ScalarType::Float64;
  int64_t position_stride = 0;  // bytes; 0 or >= 3 * sizeof(scalar)
  int64_t vertex_count = 0;
  const void* face_offsets = nullptr;  // face_count + 1 entries
  const void* face_indices = nullptr;  // face_offsets[face_count] entries
  IndexType index_type = IndexType::Int32;
  int64_t face_count = 0;
};

// As for MeshView; also Error(BadUsage) for face_offsets[0] != 0 and
// Error(BadInput) naming a face of fewer than 3 corners (or decreasing offsets).
// Whether the polygons are simple is the Session's check (it triangulates them).
LOCUS_API Mesh mesh_from_view(const PolygonMeshView& view);

}  // namespace locus
LOCUS_API_END
