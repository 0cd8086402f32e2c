// The mesh report of every front end (engine/include/locus/engine/mesh_info.hpp)
// over the kernels' one-pass analysis (kernels/.../mesh/mesh_topology.hpp).
#include "locus/engine/mesh_info.hpp"

#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/session.hpp"

namespace locus {

MeshInfo mesh_info(const Mesh& mesh) { return analyze_mesh(mesh); }  // the report's MeshInfo part

MeshInfo Session::info() const { return mesh_info(polygons()); }  // the faces as given (mesh() for triangles)

}  // namespace locus
