// A Session on the manifold sheets of a mesh that is not a manifold
// (sheets_session.hpp; the cut: kernels/.../manifold_sheets.hpp).
#include "sheets_session.hpp"

#include "locus/error.hpp"
#include "session_state.hpp"

namespace locus {

std::string SheetsSession::describe(const std::string& what, const std::string& mesh) const {
  const ManifoldSheets& s = sheets;
  std::string cut;
  auto add = [&](int64_t n, const char* one, const char* many) {
    if (n == 0) return;
    cut += (cut.empty() ? "" : ", ") + std::to_string(n) + " " + (n == 1 ? one : many);
  };
  add(s.split_vertices, "vertex split", "vertices split");
  add(s.cut_edges, "edge cut", "edges cut");
  add(s.flipped_faces, "face flipped", "faces flipped");
  add(s.dropped_faces, "face dropped", "faces dropped");
  add(s.split_faces, "face split at a T-junction", "faces split at T-junctions");
  add(s.unreferenced_vertices, "unreferenced vertex left out", "unreferenced vertices left out");
  return what + " ran on the manifold sheets of " + mesh + " (" + cut +
         "): it stays on the sheet of its vertices and does not cross a non-manifold edge or vertex";
}

namespace session_detail {

std::shared_ptr<const SheetsSession> sheets_session(State& s, const RunContext& ctx) {
  return s.sheets.get(0, ctx, [&] {
    ctx.report(0.0, "manifold sheets");
    auto out = std::make_shared<SheetsSession>();
    out->sheets = manifold_sheets(s.mesh);
    out->first_copy.assign(static_cast<size_t>(s.mesh.num_vertices()), -1);
    for (size_t v = out->sheets.vertex_of.size(); v-- > 0;)
      out->first_copy[out->sheets.vertex_of[v]] = static_cast<int32_t>(v);
    SessionOptions o;
    o.mesh_operator = OperatorChoice::Cotan;  // the sheets are manifold, with no zero-area face
    out->session = std::make_unique<Session>(Mesh(out->sheets.mesh), o);
    ctx.report(1.0, "manifold sheets");
    return std::shared_ptr<const SheetsSession>(std::move(out));
  });
}

int32_t sheet_vertex(const SheetsSession& sh, int64_t v, const char* what, const std::string& mesh) {
  const int32_t c = sh.first_copy[static_cast<size_t>(v)];
  if (c < 0)
    fail(ErrorCode::BadInput, std::string(what) + " " + std::to_string(v) + " is in no face of " + mesh +
                                  " (an unreferenced vertex): it has no surface around it");
  return c;
}

}  // namespace session_detail
}  // namespace locus
