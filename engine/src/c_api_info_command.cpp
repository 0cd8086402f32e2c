// The C API of the info command (locus_commands.h, locus_info_report): the
// engine's mesh report (engine/include/locus/engine/mesh_info.hpp) of the
// session's mesh, copied out field by field.
#include <cstring>

#include "c_api_support.hpp"
#include "locus/engine/mesh_info.hpp"

using namespace locus::c_api_detail;

extern "C" {

locus_status locus_info_run(const locus_session* session, locus_info_report* out) {
  return guarded("locus_info_run", [&] {
    const locus::Session& s = session_of(const_cast<locus_session*>(session));
    require(out != nullptr, "out is NULL");
    const locus::MeshInfo r = s.info();
    locus_info_report& o = *out;
    std::memset(&o, 0, sizeof o);
    o.n_vertices = r.n_vertices, o.n_faces = r.n_faces, o.n_edges = r.n_edges;
    for (size_t d = 0; d < r.face_degree_histogram.size(); ++d) {
      const int64_t c = r.face_degree_histogram[d];
      if (d == 3) o.triangles += c;
      else if (d == 4) o.quads += c;
      else if (d > 4) o.larger_faces += c;
    }
    o.components = r.components, o.boundary_loops = r.boundary_loops;
    o.euler_characteristic = r.euler_characteristic, o.genus = r.genus;
    o.manifold = r.manifold ? 1 : 0;
    o.non_manifold_edges = r.non_manifold_edges, o.non_manifold_vertices = r.non_manifold_vertices;
    o.degenerate_faces = r.degenerate_faces, o.unreferenced_vertices = r.unreferenced_vertices;
    for (int k = 0; k < 3; ++k) o.bbox_min[k] = r.bbox_min[k], o.bbox_max[k] = r.bbox_max[k];
    o.mean_edge_length = r.mean_edge_length;
    o.first_non_manifold_edge_v0 = r.first_non_manifold_edge_v0;
    o.first_non_manifold_edge_v1 = r.first_non_manifold_edge_v1;
    o.first_non_manifold_vertex = r.first_non_manifold_vertex;
    o.first_degenerate_face = r.first_degenerate_face;
    o.first_unreferenced_vertex = r.first_unreferenced_vertex;
  });
}

}  // extern "C"
