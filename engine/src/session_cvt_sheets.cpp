// `cvt` on a mesh that is not a manifold (thesis §3.7 needs one: a cell is a
// disk of the surface and the remesh is the cells' dual): the command's call
// sequence (session_cvt_command.cpp) runs on the mesh's manifold sheets
// (kernels/.../manifold_sheets.hpp), with the cells' operator of the Session's
// choice (the robust operator on a defective mesh), and its labels and sites
// are mapped back to the input: a vertex split into several sheet vertices
// takes the label of its first copy, an unreferenced vertex gets -1, and a
// site's face and barycentrics are those of the input face it lies in. The
// remesh is the remesh of the sheets; the report's `sheets` says how the mesh
// was cut.
#include <string>

#include "cvt_sheets.hpp"
#include "locus/engine/cvt_request.hpp"
#include "locus/error.hpp"
#include "locus/kernels/mesh/manifold_sheets.hpp"
#include "session_state.hpp"

namespace locus {

bool cvt_needs_sheets(const OperatorReport& op) {
  return op.robust && (op.non_manifold_edges || op.non_manifold_vertices || op.zero_area_faces ||
                       op.inconsistent_orientation_edges || op.unreferenced_vertices);
}

namespace {

void map_back(const Mesh& input, const ManifoldSheets& sh, CvtReport& r) {
  const std::vector<int32_t> sheet_label = std::move(r.label);
  r.label.assign(static_cast<size_t>(input.num_vertices()), -1);
  for (size_t v = sh.vertex_of.size(); v-- > 0;) r.label[sh.vertex_of[v]] = sheet_label[v];  // first copy last
  for (size_t k = 0; k < r.site_face.size(); ++k) {
    const int32_t f = r.site_face[k];
    if (f < 0) {
      r.site_vertex[k] = sh.vertex_of[r.site_vertex[k]];
      continue;
    }
    double b[3] = {0, 0, 0};
    for (int c = 0; c < 3; ++c)
      for (int j = 0; j < 3; ++j) b[j] += r.site_bary[3 * k + c] * sh.corner_bary[f][3 * c + j];
    r.site_face[k] = sh.face_of[f];
    for (int j = 0; j < 3; ++j) r.site_bary[3 * k + j] = b[j];
  }
  r.n = input.num_vertices();
  r.sheets = {true,           sh.split_vertices, sh.cut_edges,  sh.flipped_faces,
              sh.dropped_faces, sh.split_faces,  sh.unreferenced_vertices};
}

}  // namespace

CvtReport cvt_on_sheets(const Mesh& input, bool robust, const CvtRequest& req, const HeatTime& ts,
                        const HeatTime& tc, const RunContext& ctx) {
  const ManifoldSheets sh = manifold_sheets(input);
  const Mesh& m = sh.mesh;
  // Checked as the cotan operator would (manifold, no zero-area face): what the cells and the dual need.
  const std::shared_ptr<const MeshDerived> derived = session_detail::check_and_derive(m, OperatorChoice::Cotan);
  CvtReport r = cvt_command_on(m, *derived, derived->components, robust, req, ts, tc, ctx);
  map_back(input, sh, r);
  return r;
}

}  // namespace locus
