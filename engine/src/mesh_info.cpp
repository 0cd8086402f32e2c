// The mesh report of every front end (engine/include/locus/engine/mesh_info.hpp)
// over the kernels' one-pass analysis (kernels/.../mesh/mesh_topology.hpp).
#include "locus/engine/mesh_info.hpp"

#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/session.hpp"

namespace locus {

MeshInfo mesh_info(const Mesh& mesh) {
  const MeshReport r = analyze_mesh(mesh);
  MeshInfo i;
  i.n_vertices = r.n_vertices;
  i.n_faces = r.n_faces;
  i.n_edges = r.n_edges;
  i.face_degree_histogram.assign(r.face_degree_histogram.begin(), r.face_degree_histogram.end());
  i.components = r.components;
  i.boundary_loops = r.boundary_loops;
  i.euler_characteristic = r.euler_characteristic;
  i.genus = r.genus;
  i.manifold = r.manifold;
  i.non_manifold_edges = r.non_manifold_edges;
  i.non_manifold_vertices = r.non_manifold_vertices;
  i.degenerate_faces = r.degenerate_faces;
  i.unreferenced_vertices = r.unreferenced_vertices;
  for (int k = 0; k < 3; ++k) {
    i.bbox_min[k] = r.bbox_min[k];
    i.bbox_max[k] = r.bbox_max[k];
  }
  i.mean_edge_length = r.mean_edge_length;
  i.first_non_manifold_edge_v0 = r.first_non_manifold_edge_v0;
  i.first_non_manifold_edge_v1 = r.first_non_manifold_edge_v1;
  i.first_non_manifold_vertex = r.first_non_manifold_vertex;
  i.first_degenerate_face = r.first_degenerate_face;
  i.first_unreferenced_vertex = r.first_unreferenced_vertex;
  return i;
}

MeshInfo Session::info() const { return mesh_info(polygons()); }  // the faces as given (mesh() for triangles)

}  // namespace locus
