// An assimp scene flattened into one locus::Mesh (io/src/flatten_scene.cpp):
// every mesh of every node, through the node's global transform, triangles
// only, welded by position unless told not to. Internal to io/.
#pragma once
#include <string>

#include "locus/mesh.hpp"
#include "locus/mesh_io.hpp"

struct aiScene;

namespace locus::io {

// Fills `report` (counts and the file vertex -> mesh vertex map); refuses
// (BadInput, naming `name`) a scene with no triangle, a non-finite vertex or
// an out-of-range index, and (ResourceLimit) one whose flattened arrays would
// exceed opt.max_bytes, before allocating them.
Mesh flatten_scene(const aiScene& scene, const std::string& name, const ReadOptions& opt, AssetReport& report);

}  // namespace locus::io
