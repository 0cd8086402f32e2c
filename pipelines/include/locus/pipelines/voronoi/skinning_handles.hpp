// Skinning handles as vertex sets (thesis §3.7.2 with multi-source heat cells,
// §3.2): a handle is one vertex, a list of vertices, or a bone, a polyline in
// space (a rig's bone, usually inside the mesh) whose handle is the set of mesh
// vertices nearest to it: for points along every segment at a spacing of half
// the mean edge length, the nearest vertex (R^3 distance, smallest id on ties).
// Handles must be disjoint; a bone that reaches a vertex an earlier handle holds
// (two bones sharing a joint) leaves it to the earlier handle, as an artist
// would expect of a chain of bones.
//
// Thread safety: re-entrant.
#pragma once
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "locus/mesh.hpp"

namespace locus {

struct SkinningHandle {
  std::vector<int32_t> vertices;             // vertex ids (0-based); or
  std::vector<std::array<double, 3>> bone;   // a polyline of >= 2 points (used when vertices is empty)
};

// The vertices nearest to the polyline `bone` (ascending ids).
std::vector<int32_t> bone_vertices(const Mesh& m, std::span<const std::array<double, 3>> bone);

// One vertex set per handle (sorted ascending), checked: ids in range, explicit
// lists disjoint (BadUsage naming the vertex and the two handles), bones not
// empty once earlier handles took their shared vertices.
std::vector<std::vector<int32_t>> handle_vertex_sets(const Mesh& m, std::span<const SkinningHandle> handles);

}  // namespace locus
