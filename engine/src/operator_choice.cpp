// The mesh-level operator choice (engine/include/locus/engine/operator_choice.hpp).
#include "locus/engine/operator_choice.hpp"
#include "field_copy.hpp"
#include "locus/error.hpp"
#include "locus/kernels/mesh/mesh_defects.hpp"

namespace locus {

const char* operator_choice_name(OperatorChoice c) {
  switch (c) {
    case OperatorChoice::Cotan: return "cotan";
    case OperatorChoice::Robust: return "robust";
    case OperatorChoice::Auto: break;
  }
  return "auto";
}

OperatorChoice parse_operator_choice(const std::string& text) {
  if (text == "auto") return OperatorChoice::Auto;
  if (text == "cotan") return OperatorChoice::Cotan;
  if (text == "robust") return OperatorChoice::Robust;
  fail(ErrorCode::BadUsage, "operator '" + text + "': expected auto, cotan or robust");
}

namespace {

void add_count(std::string& out, int64_t count, const char* one, const char* many, const std::string& first) {
  if (count == 0) return;
  if (!out.empty()) out += ", ";
  out += std::to_string(count) + " " + (count == 1 ? one : many) + " (first " + first + ")";
}

}  // namespace

std::string OperatorReport::reason() const {
  std::string r;
  add_count(r, non_manifold_edges, "non-manifold edge", "non-manifold edges",
            std::to_string(first_non_manifold_edge_v0) + "-" + std::to_string(first_non_manifold_edge_v1));
  add_count(r, non_manifold_vertices, "non-manifold vertex", "non-manifold vertices", std::to_string(first_non_manifold_vertex));
  add_count(r, zero_area_faces, "zero-area face", "zero-area faces", "face " + std::to_string(first_zero_area_face));
  add_count(r, needle_faces, "needle face", "needle faces", "face " + std::to_string(first_needle_face));
  if (inconsistent_orientation_edges)
    r += std::string(r.empty() ? "" : ", ") + std::to_string(inconsistent_orientation_edges) +
         " inconsistently oriented edge" + (inconsistent_orientation_edges == 1 ? "" : "s");
  add_count(r, unreferenced_vertices, "unreferenced vertex", "unreferenced vertices", std::to_string(first_unreferenced_vertex));
  if (r.empty() && asked != OperatorChoice::Auto) r = "asked for";
  return r;
}

namespace {

OperatorReport report_of(const MeshDefects& d, OperatorChoice choice) {
  OperatorReport r;
  r.asked = choice;
  r.checked = true;
  LOCUS_COPY_FIELDS(r, d, non_manifold_edges, non_manifold_vertices, zero_area_faces, needle_faces,
                    inconsistent_orientation_edges, unreferenced_vertices, first_non_manifold_edge_v0,
                    first_non_manifold_edge_v1, first_non_manifold_vertex, first_zero_area_face, first_needle_face,
                    first_unreferenced_vertex);
  r.robust = choice == OperatorChoice::Robust || d.any();
  return r;
}

}  // namespace

OperatorReport choose_operator(const Mesh& m, OperatorChoice choice) {
  if (choice == OperatorChoice::Cotan) {
    OperatorReport r;
    r.asked = choice;
    return r;
  }
  return report_of(detect_mesh_defects(m), choice);
}

OperatorReport choose_operator_from(const Mesh& m, const EdgeIncidence& inc, const MeshReport& report,
                                    OperatorChoice choice) {
  if (choice == OperatorChoice::Cotan) {
    OperatorReport r;
    r.asked = choice;
    return r;
  }
  return report_of(detect_mesh_defects(m, inc, report), choice);
}

}  // namespace locus
