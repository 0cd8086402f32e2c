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
