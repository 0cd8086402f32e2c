// A Session on the manifold sheets of a mesh that is not a manifold
// (kernels/.../manifold_sheets.hpp), for the commands whose geometry needs one
// tangent plane per vertex: the log map and deform run there on the cotan
// operator and their results are mapped back to the input's vertices
// (session_logmap_command.cpp, session_deform_command.cpp). Built once per
// positions and kept in the State. Internal to the engine.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "locus/kernels/mesh/manifold_sheets.hpp"
#include "locus/session.hpp"

namespace locus {

struct SheetsSession {
  ManifoldSheets sheets;
  std::vector<int32_t> first_copy;  // per input vertex: its first sheet vertex, -1 when unreferenced
  std::unique_ptr<Session> session;  // cotan, on sheets.mesh
  // "the log map ran on the manifold sheets of FILE (2 vertices split, ...)": for warnings.
  std::string describe(const std::string& what, const std::string& mesh) const;
};

namespace session_detail {
struct State;
// The sheets of s.mesh and their Session, built once per positions.
std::shared_ptr<const SheetsSession> sheets_session(State& s, const RunContext& ctx);
// The sheet vertex of input vertex v for a request's `what` (its first copy); BadInput when v is in no face.
int32_t sheet_vertex(const SheetsSession& sh, int64_t v, const char* what, const std::string& mesh);
}  // namespace session_detail

}  // namespace locus
