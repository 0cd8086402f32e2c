// The C API of the info command (locus_commands.h, locus_info_report): the
// engine's mesh report (engine/include/locus/engine/mesh_info.hpp) of the
// session's mesh, copied out field by field.
#include <cstring>

#include "c_api_support.hpp"
#include "field_copy.hpp"
#include "locus/engine/mesh_info.hpp"

using namespace locus::c_api_detail;

// The report's numbers that the C struct names alike.
#define LOCUS_MESH_INFO_NUMBERS                                                                                   \
  n_vertices, n_faces, n_edges, components, boundary_loops, euler_characteristic, genus, manifold,               \
      non_manifold_edges, non_manifold_vertices, degenerate_faces, unreferenced_vertices, mean_edge_length,      \
      first_non_manifold_edge_v0, first_non_manifold_edge_v1, first_non_manifold_vertex, first_degenerate_face, \
      first_unreferenced_vertex

extern "C" {

locus_status locus_info_run(const locus_session* session, locus_info_report* out) {
  return guarded("locus_info_run", [&] {
    const locus::Session& s = session_of(const_cast<locus_session*>(session));
    require(out != nullptr, "out is NULL");
    const locus::MeshInfo r = s.info();
    locus_info_report& o = *out;
    std::memset(&o, 0, sizeof o);
    LOCUS_COPY_FIELDS(o, r, LOCUS_MESH_INFO_NUMBERS);
    for (size_t d = 0; d < r.face_degree_histogram.size(); ++d) {
      const int64_t c = r.face_degree_histogram[d];
      if (d == 3) o.triangles += c;
      else if (d == 4) o.quads += c;
      else if (d > 4) o.larger_faces += c;
    }
    for (int k = 0; k < 3; ++k) o.bbox_min[k] = r.bbox_min[k], o.bbox_max[k] = r.bbox_max[k];
  });
}

}  // extern "C"
