// `locus geodesic MESH --source V [--fraction f] [--t T] -o dist.ply`: heat
// geodesic distance from one vertex, on the whole mesh (--fraction 1, the
// default) or localized to the geodesic disk of round(f * n) vertices around
// the source; a client of locus::Session::geodesic
// (engine/include/locus/engine/geodesic_requests.hpp), which owns the
// validation, defaults and computation. Output: vertex properties `distance`
// (NaN without a value) and `valid`; JSON: the report's statistics.
#include <memory>
#include <ostream>

#include "locus/engine/geodesic_requests.hpp"
#include "locus/session.hpp"
#include "tools/cli/cli_common.hpp"

namespace locus::cli {
namespace {

struct GeodesicCli {
  GeodesicRequest request;  // every option of the command but the common ones and the preview
  PreviewOptions preview;   // --preview out.png: distance colour map
};

Json geodesic_json(const CommonOptions& opt, const Input& in, const GeodesicReport& r) {
  const bool polygon = r.method == "heat-full-polygon";
  Json j{{"command", "geodesic"}, {"input", input_json(opt, in)}};
  j["source"] = r.source;
  j["method"] = r.method;
  j["fraction"] = r.fraction;
  j["t_factor"] = r.t_factor;
  j["t_spec"] = r.t_spec;
  j["t"] = r.t;
  j["h"] = r.h;
  j["patch_size"] = r.patch_size;
  j["max_distance"] = r.max_distance;
  if (!polygon) j["unreachable"] = r.unreachable;  // vertices in other connected components (written as NaN)
  j["precompute_s"] = r.precompute_s;
  if (!polygon) j["patch_s"] = r.patch_s;
  j["query_s"] = r.query_s;
  if (r.factor_cache.used()) j["factor_cache"] = factor_cache_json(r.factor_cache);
  if (!polygon) j["heat_underflow_vertices"] = r.heat_underflow_vertices;  // also a warning
  if (r.heat_underflow_vertices > 0) {
    j["t_avoiding_underflow"] = r.t_avoiding_underflow;
    j["warnings"] = r.warnings;
  }
  j["timings"] = timings(in);
  return j;
}

int run_geodesic(const CommonOptions& opt, const GeodesicCli& go, const RunContext& ctx) {
  check_request(go.request);
  note_deprecated_t_factor(go.request.t_factor);
  check_preview_options(go.preview);
  const Input in = load_input(opt, ctx, keeps_polygons(go.request) ? PolygonFaces::Keep : PolygonFaces::Triangulate);
  check_file_vertex("--source", go.request.source, in, opt);
  const Session session{Mesh(in.mesh), session_options(in)};
  const GeodesicReport r = session.geodesic(go.request, ctx);
  for (const std::string& w : r.warnings) log("warning: " + w);
  if (!opt.output.empty()) {
    WriteOptions wo = carried_attributes(in);
    add_result(wo, {"distance", VertexProperty::Type::Double, r.distance});
    add_result(wo, {"valid", VertexProperty::Type::Int, r.valid});
    write_output_mesh(opt, output_faces(in), wo);
  }
  const int32_t s = r.source;
  write_preview(in.mesh, r.distance, PreviewKind::Scalar, go.preview,  // NaN (no value): grey
                {"geodesic distance from vertex " + std::to_string(s) +
                     (r.method == "heat-local" ? " (patch of " + std::to_string(r.patch_size) + " vertices)" : ""),
                 {{in.mesh.x[s], in.mesh.y[s], in.mesh.z[s]}},
                 "source"});
  emit(opt, geodesic_json(opt, in, r), [&](std::ostream& os) {
    os << opt.mesh_path << ": heat geodesic " << (r.method == "heat-full-polygon" ? "on polygons " : "")
       << "from vertex " << s << " (" << r.method << ", t = " << r.t << ")\n  patch " << r.patch_size
       << " vertices, max distance " << r.max_distance << "\n  precompute " << r.precompute_s << " s, query "
       << r.query_s << " s\n";
  });
  return 0;
}

}  // namespace

void register_logmap_command(CommandTable& table);  // tools/cli/cmd_logmap.cpp

// `geodesic` and `logmap` (one registration line in main.cpp for both).
void register_geodesic_commands(CommandTable& table) {
  register_logmap_command(table);
  auto go = std::make_shared<GeodesicCli>();
  CLI::App* app = table.add("geodesic", "Heat geodesic distance from a vertex (whole mesh or localized to a patch)",
                            [go](const CommonOptions& o, const RunContext& ctx) { return run_geodesic(o, *go, ctx); });
  GeodesicRequest& q = go->request;
  app->add_option("--source", q.source, "Source vertex (0-based)")->required();
  app->add_option("--fraction", q.fraction, "Patch size as a fraction of the vertices (default 1: whole mesh)");
  add_heat_method_time(app, q.t, q.t_factor,
                       "4h2 (polygon meshes 8h2), for accuracy; a query costs the same at any t");
  add_preview_option(app, go->preview);
  add_factor_cache_options(app, q.save, q.load);
}

}  // namespace locus::cli
