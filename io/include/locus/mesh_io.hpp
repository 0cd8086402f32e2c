// Mesh file reading and writing (io/). Formats by extension: .obj .off .ply.
//
// Readers treat files as hostile: any malformed content raises locus::Error
// (ErrorCode::BadInput) naming the file and the line / byte offset / element.
// Readers check only what the format says (syntax, counts, index ranges, finite
// coordinates, faces with >= 3 distinct vertices); topological questions
// (manifoldness, components, degenerate areas) are for mesh_topology.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "locus/mesh.hpp"

#include "locus/export.h"

LOCUS_API_BEGIN
namespace locus {

struct ReadOptions {
  // Refuse files whose header counts would need more than this many bytes.
  uint64_t max_bytes = uint64_t(8) << 30;
};

Mesh read_mesh(const std::string& path, const ReadOptions& opt = {});
// Parses an in-memory buffer; `format` is "obj", "off" or "ply"; `name` is used in messages.
Mesh read_mesh_from_memory(const char* data, size_t size, const std::string& format, const std::string& name,
                           const ReadOptions& opt = {});

// A named per-vertex property for writers.
struct VertexProperty {
  enum class Type { Float, Double, Int };
  std::string name;
  Type type = Type::Double;
  std::vector<double> values;  // nv values (ints stored exactly as doubles)
};

struct WriteOptions {
  std::vector<VertexProperty> vertex_properties;  // PLY: extra vertex properties
  const std::vector<double>* uv = nullptr;        // 2*nv texture coordinates (OBJ vt, PLY u/v)
  bool binary = true;                             // PLY: binary little endian or ascii
};

void write_mesh(const std::string& path, const Mesh& mesh, const WriteOptions& opt = {});

}  // namespace locus
LOCUS_API_END
