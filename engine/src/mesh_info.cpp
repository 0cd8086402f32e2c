// The mesh report of every front end (engine/include/locus/engine/mesh_info.hpp)
// over the kernels' one-pass analysis (kernels/.../mesh/mesh_topology.hpp).
#include "locus/engine/mesh_info.hpp"

#include "field_copy.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "mesh_info_fields.hpp"
#include "locus/session.hpp"

namespace locus {

MeshInfo mesh_info(const Mesh& mesh) {
  const MeshReport r = analyze_mesh(mesh);
  MeshInfo i;
  LOCUS_COPY_FIELDS(i, r, LOCUS_MESH_INFO_NUMBERS);
  i.face_degree_histogram.assign(r.face_degree_histogram.begin(), r.face_degree_histogram.end());
  for (int k = 0; k < 3; ++k) i.bbox_min[k] = r.bbox_min[k], i.bbox_max[k] = r.bbox_max[k];
  return i;
}

MeshInfo Session::info() const { return mesh_info(polygons()); }  // the faces as given (mesh() for triangles)

}  // namespace locus
