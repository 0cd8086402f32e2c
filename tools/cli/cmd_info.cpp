// `locus info MESH`: what the mesh is (sizes, face degrees, topology, bounding
// box, mean edge length) and what is wrong with it (non-manifold edges and
// vertices, degenerate faces, unreferenced vertices), from locus::analyze_mesh.
// info reports problems but does not fail on them: it is the tool a user runs
// to find out why another command refused the file. Only an unreadable file
// fails (exit 3).
#include <iomanip>
#include <ostream>

#include "locus/kernels/mesh/mesh_topology.hpp"
#include "tools/cli/cli_common.hpp"

namespace locus::cli {
namespace {

Json report_json(const MeshReport& r) {
  Json hist = Json::object();
  for (size_t d = 0; d < r.face_degree_histogram.size(); ++d)
    if (r.face_degree_histogram[d] != 0) hist[std::to_string(d)] = r.face_degree_histogram[d];
  Json j;
  j["n_vertices"] = r.n_vertices;
  j["n_faces"] = r.n_faces;
  j["n_edges"] = r.n_edges;
  j["face_degree_histogram"] = hist;
  j["components"] = r.components;
  j["boundary_loops"] = r.boundary_loops;
  j["euler_characteristic"] = r.euler_characteristic;
  // Genus is only defined for a connected manifold; analyze_mesh says -1 otherwise.
  j["genus"] = r.genus >= 0 ? Json(r.genus) : Json(nullptr);
  j["manifold"] = r.manifold;
  j["non_manifold_edges"] = r.non_manifold_edges;
  j["non_manifold_vertices"] = r.non_manifold_vertices;
  j["degenerate_faces"] = r.degenerate_faces;
  j["unreferenced_vertices"] = r.unreferenced_vertices;
  j["bbox"] = {{"min", {r.bbox_min[0], r.bbox_min[1], r.bbox_min[2]}},
               {"max", {r.bbox_max[0], r.bbox_max[1], r.bbox_max[2]}}};
  j["mean_edge_length"] = r.mean_edge_length;
  return j;
}

void print_human(std::ostream& os, const CommonOptions& opt, const Input& in, const MeshReport& r, double analysis_s) {
  os << opt.mesh_path;
  if (opt.subdivide > 0) os << " (subdivided " << opt.subdivide << "x)";
  os << "\n  vertices " << r.n_vertices << ", faces " << r.n_faces << ", edges " << r.n_edges << "\n  face degrees:";
  for (size_t d = 0; d < r.face_degree_histogram.size(); ++d)
    if (r.face_degree_histogram[d] != 0) os << " " << d << ":" << r.face_degree_histogram[d];
  os << "\n  components " << r.components << ", boundary loops " << r.boundary_loops << ", Euler characteristic "
     << r.euler_characteristic << ", genus ";
  if (r.genus >= 0)
    os << r.genus;
  else
    os << "undefined (not a connected manifold)";
  os << "\n  manifold " << (r.manifold ? "yes" : "no");
  if (r.non_manifold_edges > 0) {
    os << "; " << r.non_manifold_edges << " non-manifold edges";
    if (r.first_non_manifold_edge_v0 >= 0)
      os << " (first: " << r.first_non_manifold_edge_v0 << "-" << r.first_non_manifold_edge_v1 << ")";
  }
  if (r.non_manifold_vertices > 0) os << "; " << r.non_manifold_vertices << " non-manifold vertices";
  os << "\n  degenerate faces " << r.degenerate_faces;
  if (r.first_degenerate_face >= 0) os << " (first: face " << r.first_degenerate_face << ")";
  os << ", unreferenced vertices " << r.unreferenced_vertices;
  if (r.first_unreferenced_vertex >= 0) os << " (first: vertex " << r.first_unreferenced_vertex << ")";
  os << std::setprecision(6) << "\n  bbox [" << r.bbox_min[0] << ", " << r.bbox_min[1] << ", " << r.bbox_min[2]
     << "] - [" << r.bbox_max[0] << ", " << r.bbox_max[1] << ", " << r.bbox_max[2] << "]\n  mean edge length "
     << r.mean_edge_length;
  if (in.op.robust) os << "\n  operator robust (" << in.op.reason() << ")";
  if (in.attributes.asset) {
    const AssetReport& a = in.attributes.asset_report;
    os << "\n  " << a.format << ": " << a.file_vertices << " file vertices, " << a.welded_vertices
       << " welded by position (--no-weld keeps them)";
  }
  os << "\n  load " << in.load_s << " s";
  if (opt.subdivide > 0) os << ", subdivide " << in.subdivide_s << " s";
  os << ", analysis " << analysis_s << " s\n";
}

int run_info(const CommonOptions& opt, const RunContext& ctx) {
  Input in = load_input(opt, ctx, PolygonFaces::Keep);
  ctx.check_cancel();
  Stopwatch sw;
  const MeshReport r = analyze_mesh(in.mesh);
  const double analysis_s = sw.seconds();

  Json j{{"command", "info"}, {"input", input_json(opt, in)}};
  j.update(report_json(r));
  j["timings"] = timings(in, {{"analysis_s", analysis_s}});
  write_output_mesh(opt, in.mesh, carried_attributes(in));
  emit(opt, j, [&](std::ostream& os) { print_human(os, opt, in, r, analysis_s); });
  return 0;
}

}  // namespace

void register_info_command(CommandTable& table) {
  table.add("info", "Sizes, topology and problems of a mesh (never fails on a readable file)", run_info);
}

}  // namespace locus::cli
