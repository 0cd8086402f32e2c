// The input and output files of a command (cli_input.hpp).
#include "tools/cli/cli_input.hpp"
#include "tools/cli/written_files.hpp"

#include <algorithm>

#include "locus/error.hpp"
#include "locus/io/file_extension.hpp"

namespace locus::cli {

namespace {

Input load(const CommonOptions& opt, const RunContext& ctx, PolygonFaces faces, bool choose_operator) {
  MeshInputOptions mo;
  mo.choose_operator = choose_operator;
  mo.subdivide = opt.subdivide;
  mo.faces = faces;
  mo.weld = !opt.no_weld;
  mo.mesh_operator = parse_operator_choice(opt.mesh_operator);
  Input in = load_mesh_input(opt.mesh_path, mo, ctx);
  report_input(in.load_s, in.subdivide_s);
  return in;
}

}  // namespace

Input load_input(const CommonOptions& opt, const RunContext& ctx, PolygonFaces faces) {
  return load(opt, ctx, faces, true);
}

Input load_input_for_session(const CommonOptions& opt, const RunContext& ctx) {
  return load(opt, ctx, PolygonFaces::Triangulate, false);
}

void take_session_operator(Input& in, const Session& session, const RunContext& ctx) {
  if (in.op.checked) return;
  in.op = session.operator_report();
  if (in.op.robust && in.op.any_defect()) ctx.note(in.path + ": the robust operator (" + in.op.reason() + ")");
}

SessionOptions session_options(const Input& in) {
  SessionOptions so;
  // The loader looked for the defects already: the Session need not look again.
  so.mesh_operator = !in.op.checked ? in.mesh_operator : in.op.robust ? OperatorChoice::Robust : OperatorChoice::Cotan;
  so.cotan_chosen_by_auto = in.op.checked && in.mesh_operator == OperatorChoice::Auto;
  return so;
}

Json operator_json(const OperatorReport& op) {
  Json j{{"used", op.used()}, {"asked", operator_choice_name(op.asked)}};
  if (op.checked) {
    j["reason"] = op.reason();
    j["defects"] = {{"non_manifold_edges", op.non_manifold_edges},
                    {"non_manifold_vertices", op.non_manifold_vertices},
                    {"zero_area_faces", op.zero_area_faces},
                    {"needle_faces", op.needle_faces},
                    {"inconsistent_orientation_edges", op.inconsistent_orientation_edges},
                    {"unreferenced_vertices", op.unreferenced_vertices}};
  }
  return j;
}

Json weld_json(const Input& in) {
  const AssetReport& a = in.attributes.asset_report;
  Json j{{"format", a.format},
         {"welded", a.welded_vertices > 0 || a.file_vertices != in.mesh.num_vertices()},
         {"file_vertices", a.file_vertices},
         {"welded_vertices", a.welded_vertices},
         {"vertices", in.mesh.num_vertices()},
         {"collapsed_faces", a.collapsed_faces},
         {"map", "results are per welded vertex; file vertex k (the scene's meshes flattened in node order) has "
                 "the result of vertex file_to_vertex[k]; --no-weld keeps the file's vertices"}};
  if (in.subdivide == 0) j["file_to_vertex"] = a.file_to_vertex;
  return j;
}

Json input_json(const CommonOptions& opt, const Input& in) {
  Json j{{"file", opt.mesh_path},
         {"subdivide", opt.subdivide},
         {"n_vertices", in.mesh.num_vertices()},
         {"n_faces", in.mesh.num_faces()}};
  if (in.triangulated())
    j["triangulated"] = {{"polygons", in.polygons.num_faces()}, {"triangles", in.mesh.num_faces()},
                         {"seconds", in.triangulate_s}};
  // Absent on a clean mesh with --operator auto (the cotan operator, as without the option).
  if (in.op.robust || in.mesh_operator != OperatorChoice::Auto) j["operator"] = operator_json(in.op);
  if (in.attributes.asset) j["weld"] = weld_json(in);
  return j;
}

void check_file_vertex(const std::string& option, int64_t v, const Input& in, const CommonOptions& opt) {
  const int32_t n = in.mesh.num_vertices();
  if (v >= n)
    fail(ErrorCode::BadInput, option + " " + std::to_string(v) + " is not a vertex of " + opt.mesh_path + " (" +
                                  std::to_string(n) + " vertices, ids 0.." + std::to_string(n - 1) + ")");
}

SurfacePoint point_on_file_face(const Input& in, const SurfacePoint& p, const std::string& what) {
  if (!in.triangulated() || p.face < 0) return p;
  const Mesh& poly = in.polygons;
  if (p.face >= poly.num_faces())
    fail(ErrorCode::BadInput, what + ": face " + std::to_string(p.face) + " does not exist (" +
                                  std::to_string(poly.num_faces()) + " faces)");
  const auto fv = poly.face(p.face);
  double x[3] = {0, 0, 0};
  for (int k = 0; k < 3; ++k) {
    x[0] += p.bary[k] * poly.x[fv[k]];
    x[1] += p.bary[k] * poly.y[fv[k]];
    x[2] += p.bary[k] * poly.z[fv[k]];
  }
  // The polygon's triangles are consecutive in face order; barycentrics of x
  // in each by least squares (x may sit off a warped polygon's triangles).
  const auto first = std::lower_bound(in.face_of.begin(), in.face_of.end(), p.face);
  for (auto it = first; it != in.face_of.end() && *it == p.face; ++it) {
    const int32_t t = static_cast<int32_t>(it - in.face_of.begin());
    const auto tv = in.mesh.face(t);
    const double a[3] = {in.mesh.x[tv[0]], in.mesh.y[tv[0]], in.mesh.z[tv[0]]};
    const double e1[3] = {in.mesh.x[tv[1]] - a[0], in.mesh.y[tv[1]] - a[1], in.mesh.z[tv[1]] - a[2]};
    const double e2[3] = {in.mesh.x[tv[2]] - a[0], in.mesh.y[tv[2]] - a[1], in.mesh.z[tv[2]] - a[2]};
    const double d[3] = {x[0] - a[0], x[1] - a[1], x[2] - a[2]};
    const double g11 = e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2], g12 = e1[0] * e2[0] + e1[1] * e2[1] + e1[2] * e2[2],
                 g22 = e2[0] * e2[0] + e2[1] * e2[1] + e2[2] * e2[2];
    const double r1 = e1[0] * d[0] + e1[1] * d[1] + e1[2] * d[2], r2 = e2[0] * d[0] + e2[1] * d[1] + e2[2] * d[2];
    const double det = g11 * g22 - g12 * g12;
    if (!(det > 0)) continue;
    const double b1 = (g22 * r1 - g12 * r2) / det, b2 = (g11 * r2 - g12 * r1) / det, b0 = 1 - b1 - b2;
    if (b0 >= -1e-9 && b1 >= -1e-9 && b2 >= -1e-9) {
      SurfacePoint q;
      q.face = t;
      q.bary = {std::max(b0, 0.0), std::max(b1, 0.0), std::max(b2, 0.0)};
      const double s = q.bary[0] + q.bary[1] + q.bary[2];
      for (double& b : q.bary) b /= s;
      return q;
    }
  }
  fail(ErrorCode::BadInput, what + ": the point with weights of corners 0, 1, 2 of face " + std::to_string(p.face) +
                                " lies outside that polygon");
}


Mesh with_positions(const Input& in, const Mesh& moved) {
  if (!in.triangulated()) return moved;
  Mesh out = in.polygons;
  out.x = moved.x;
  out.y = moved.y;
  out.z = moved.z;
  return out;
}

void check_uv_output(const CommonOptions& opt, const std::string& command) {
  if (!opt.output.empty() && io::lower_extension(opt.output) == "off")
    fail(ErrorCode::BadUsage, command + ": -o " + opt.output +
                                  ": OFF has no texture coordinates for the result's UVs; use .obj or .ply");
}

void refuse_output(const CommonOptions& opt, const std::string& command, const std::string& result) {
  if (!opt.output.empty())
    fail(ErrorCode::BadUsage, command + ": -o " + opt.output + ": this command writes no file; " + result);
}

WriteOptions carried_attributes(const Input& in, bool positions_changed, bool result_uv) {
  WriteOptions wo;
  wo.float_positions = in.attributes.float_positions;
  for (const VertexProperty& p : in.attributes.vertex) {
    if (static_cast<int32_t>(p.values.size()) != in.mesh.num_vertices()) continue;
    if (positions_changed && (p.name == "nx" || p.name == "ny" || p.name == "nz")) continue;
    if (result_uv && (p.name == "u" || p.name == "v")) continue;
    wo.vertex_properties.push_back(p);
  }
  return wo;
}

void add_result(WriteOptions& wo, VertexProperty p) {
  auto& props = wo.vertex_properties;
  props.erase(std::remove_if(props.begin(), props.end(), [&](const VertexProperty& q) { return q.name == p.name; }),
              props.end());
  if (wo.off_colour.empty()) wo.off_colour = p.name;  // OFF shows the first result, not an input attribute
  props.push_back(std::move(p));
}

void write_output_mesh(const CommonOptions& opt, const Mesh& m, const WriteOptions& wo) {
  if (opt.output.empty()) return;
  write_mesh(opt.output, m, wo);
  log_written(opt.output);
}

}  // namespace locus::cli
