// Mesh file reading and writing (io/). Formats by extension: .obj .off .ply
// with locus's own readers; every other format assimp reads (glTF 2.0 .gltf
// and .glb, FBX, Collada .dae, STL, 3MF, 3DS, DirectX .x, ...) through assimp,
// flattened into one triangle mesh (io/src/read_assimp.cpp).
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

struct LOCUS_API ReadOptions {
  // Refuse files whose header counts would need more than this many bytes.
  uint64_t max_bytes = uint64_t(8) << 30;
  // Asset formats read through assimp: weld the flattened scene's vertices by
  // position (exporters split a vertex at every UV or normal seam; welding
  // gives back the surface the artist sees). false keeps the file's vertices.
  // OBJ, OFF and PLY are never welded.
  bool weld = true;
};

// How an asset file (one read through assimp) became one mesh. Its "file
// vertices" are the vertices of the scene's meshes in flattening order: the
// node tree depth first in file order, each node's meshes in order, each
// mesh's vertices in order (a mesh used by two nodes is counted twice).
struct LOCUS_API AssetReport {
  std::string format;                 // assimp's name of the importer ("glTF2 Importer", ...)
  int32_t mesh_instances = 0;         // node meshes flattened (meshes without triangles are skipped)
  int64_t file_vertices = 0;          // vertices of the flattened meshes
  int64_t welded_vertices = 0;        // file_vertices - mesh vertices (0 when not welding)
  std::vector<int32_t> file_to_vertex;  // file vertex -> mesh vertex (identity when not welding)
  int64_t skipped_points = 0;         // point primitives (not part of a surface)
  int64_t skipped_lines = 0;          // line primitives
  int64_t collapsed_faces = 0;        // triangles whose corners welding merged (dropped)
  int32_t skipped_meshes = 0;         // node meshes with no triangle (points or lines only)
};


// A named per-vertex property (readers' attributes, writers' results).
struct LOCUS_API VertexProperty {
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
struct LOCUS_API MeshAttributes {
  std::vector<VertexProperty> vertex;
  bool float_positions = false;
  std::vector<std::string> notes;
  bool asset = false;  // read through assimp: `asset_report` says how
  AssetReport asset_report;
};

LOCUS_API Mesh read_mesh(const std::string& path, const ReadOptions& opt = {});
// Also fills `attributes` (when not null) with what the file holds beyond the mesh.
LOCUS_API Mesh read_mesh(const std::string& path, const ReadOptions& opt, MeshAttributes* attributes);
// Parses an in-memory buffer; `format` is an extension read_mesh knows ("obj",
// "off", "ply", "glb", "fbx", ...); `name` is used in messages. A buffer read
// through assimp can reference no other file (a .gltf's external buffers are
// refused; embedded data: URIs are fine).
LOCUS_API Mesh read_mesh_from_memory(const char* data, size_t size, const std::string& format, const std::string& name,
                                     const ReadOptions& opt = {}, MeshAttributes* attributes = nullptr);

struct LOCUS_API WriteOptions {
  std::vector<VertexProperty> vertex_properties;  // PLY: extra vertex properties; OBJ: a '#vp' comment block
  const std::vector<double>* uv = nullptr;        // 2*nv texture coordinates (OBJ vt, PLY u/v)
  bool binary = true;                             // PLY: binary little endian or ascii
  bool float_positions = false;                   // PLY: x y z as float (an input stored so stays so)
  std::string off_colour;                         // OFF: the property shown as colours ("" = the first)
};

// Whether read_mesh reads files with this extension (lower case, no dot).
LOCUS_API bool is_readable_mesh_extension(const std::string& ext);

LOCUS_API void write_mesh(const std::string& path, const Mesh& mesh, const WriteOptions& opt = {});

}  // namespace locus
LOCUS_API_END
