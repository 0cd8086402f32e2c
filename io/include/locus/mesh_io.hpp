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

// A named per-vertex property (readers' attributes, writers' results).
struct VertexProperty {
  // The PLY scalar types; Int is int32.
  enum class Type { Float, Double, Int, Int8, UInt8, Int16, UInt16, UInt32 };
  std::string name;
  Type type = Type::Double;
  std::vector<double> values;  // nv values (integers and floats stored exactly as doubles)
};

// What a file holds beyond positions and faces, for carrying it to outputs
// that keep the input's vertices: every scalar vertex
// property of a PLY other than x, y, z (normals nx ny nz, colours red green
// blue alpha, texture coordinates, custom ones), in file order with their
// types; of an OBJ the vt and vn of each vertex (as u v and nx ny nz, when
// all corners of a vertex agree) and the properties of a locus '#vp' block;
// of an OFF what its keyword announces (N normals, C colours, ST u v);
// and whether the positions were stored as float. `notes` say what was
// found but could not be kept per vertex (an OBJ's texture seams).
struct MeshAttributes {
  std::vector<VertexProperty> vertex;
  bool float_positions = false;
  std::vector<std::string> notes;
};

Mesh read_mesh(const std::string& path, const ReadOptions& opt = {});
// Also fills `attributes` (when not null) with what the file holds beyond the mesh.
Mesh read_mesh(const std::string& path, const ReadOptions& opt, MeshAttributes* attributes);
// Parses an in-memory buffer; `format` is "obj", "off" or "ply"; `name` is used in messages.
Mesh read_mesh_from_memory(const char* data, size_t size, const std::string& format, const std::string& name,
                           const ReadOptions& opt = {}, MeshAttributes* attributes = nullptr);

struct WriteOptions {
  std::vector<VertexProperty> vertex_properties;  // PLY: extra vertex properties; OBJ: a '#vp' comment block
  const std::vector<double>* uv = nullptr;        // 2*nv texture coordinates (OBJ vt, PLY u/v)
  bool binary = true;                             // PLY: binary little endian or ascii
  bool float_positions = false;                   // PLY: x y z as float (an input stored so stays so)
  std::string off_colour;                         // OFF: the property shown as colours ("" = the first)
};

void write_mesh(const std::string& path, const Mesh& mesh, const WriteOptions& opt = {});

}  // namespace locus
LOCUS_API_END
