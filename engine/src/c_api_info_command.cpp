// The C API of the info command (locus_commands.h, locus_info_report): the
// engine's mesh report (engine/include/locus/engine/mesh_info.hpp) of the
// session's mesh, copied out field by field.
#include <cstring>

#include "c_api_support.hpp"
#include "field_copy.hpp"
#include "locus/engine/mesh_info.hpp"
#include "mesh_info_fields.hpp"

using namespace locus::c_api_detail;

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
