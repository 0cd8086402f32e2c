// The per-format readers behind read_mesh / read_mesh_from_memory
// (io/src/read_mesh.cpp dispatches on the extension). Internal to io/.
// Each parses a complete in-memory file; `name` is used in error messages.
#pragma once
#include <string>
#include <string_view>

#include "locus/mesh.hpp"
#include "locus/mesh_io.hpp"

namespace locus::io {

// `attributes` (may be null) receives per-vertex texture coordinates (u, v
// from vt) and normals (nx, ny, nz from vn) when every corner of a vertex
// names the same values, and the properties of a locus '#vp' block.
Mesh read_obj(std::string_view data, const std::string& name, const ReadOptions& opt,
              MeshAttributes* attributes = nullptr);
// `attributes` (may be null) receives what the keyword ([ST][C][N]OFF) announces per vertex.
Mesh read_off(std::string_view data, const std::string& name, const ReadOptions& opt,
              MeshAttributes* attributes = nullptr);
// `attributes` (may be null) receives the vertex properties other than x, y, z.
Mesh read_ply(std::string_view data, const std::string& name, const ReadOptions& opt,
              MeshAttributes* attributes = nullptr);

}  // namespace locus::io

namespace locus::io {

// Whether assimp reads files with this extension (lower case, no dot). Also
// true for obj, off and ply, which read_mesh gives to the readers above.
bool assimp_reads_extension(const std::string& ext);

// Any format assimp reads (io/src/read_assimp.cpp), flattened into one
// triangle mesh and welded by position unless opt.weld is false. `format` is
// the extension that picks assimp's importer. `sibling_dir`: the folder a
// .gltf's external buffers may be read from ("" = none: only `data`).
// `attributes` (may be null) receives the AssetReport.
Mesh read_assimp(std::string_view data, const std::string& format, const std::string& name,
                 const std::string& sibling_dir, const ReadOptions& opt, MeshAttributes* attributes = nullptr);

}  // namespace locus::io
