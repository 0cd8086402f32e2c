// `locus geodesic MESH --source V [--fraction f] [--t T] -o dist.ply`:
// heat geodesic distance from one vertex (thesis §6.4.1, Crane et al.), on the
// whole mesh with full solves (--fraction 1, the default) or localized to the
// geodesic disk of round(f * n) vertices around the source with exact subset
// solves (§6.4.2; pipelines/include/locus/pipelines/geodesic/heat_geodesic.hpp). Output: PLY vertex property
// `distance` (-1 outside the patch); JSON: precompute_s, query_s, patch_size,
// the maximum distance and the radius of the patch.
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <ostream>

#include "locus/error.hpp"
#include "locus/mesh_io.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/kernels/mesh/patch_grower.hpp"
#include "locus/kernels/mesh/polygon_triangulation.hpp"
#include "locus/pipelines/geodesic/heat_geodesic.hpp"
#include "locus/pipelines/geodesic/polygon_heat_geodesic.hpp"
#include "tools/cli/cli_common.hpp"
#include "tools/cli/written_files.hpp"
#include "tools/cli/heat_method_cache.hpp"

namespace locus::cli {
namespace {

struct GeodesicOptions {
  int64_t source = -1;
  double fraction = 1.0;
  HeatTimeOptions time;  // --t (default 4h2, polygon meshes 8h2), --t-factor (deprecated)
  PreviewOptions preview;  // --preview out.png: distance colour map
  FactorCacheOptions cache;
  bool t_given() const { return !time.t_text.empty() || !time.t_factor.empty(); }  // else each mesh kind's default
};

bool local_fraction(double fraction) { return fraction < 1.0; }

// Polygon meshes (quads, mixed, n-gons): the whole-mesh heat method on the
// polygon operators (pipelines/include/locus/pipelines/geodesic/polygon_heat_geodesic.hpp),
// without the triangulation's diagonals. Localized queries and factor caches
// are triangle-only for now: with those, polygons are triangulated on load.
bool polygon_native(const GeodesicOptions& go) {
  return !local_fraction(go.fraction) && go.cache.save.empty() && go.cache.load.empty();
}

int run_polygon_geodesic(const CommonOptions& opt, const GeodesicOptions& go, const TimeSpec& time, const Input& in,
                         int32_t source, const RunContext& ctx) {
  // The polygons must be simple (the triangulation's checks name a crossing or
  // flat face of the file, where the polygon operators would only see a
  // degenerate triangle of their own).
  (void)triangulate_polygons(in.mesh, opt.mesh_path);
  const int32_t n = in.mesh.num_vertices();
  Stopwatch sw;
  PolygonHeatGeodesicOptions po;  // t_factor 8 unless given (see polygon_heat_geodesic.hpp)
  if (go.t_given()) po.t_factor = heat_t_factor(time, time.times_h2 ? 0.0 : mean_edge_length(in.mesh));
  const PolygonHeatGeodesic geo(in.mesh, po, ctx);
  const double precompute_s = sw.seconds();
  std::vector<double> distance(static_cast<size_t>(n)), valid(static_cast<size_t>(n), 1.0);
  sw.restart();
  geo.query_full(source, distance);
  const double query_s = sw.seconds();
  double dmax = 0;
  for (double d : distance) {
    if (!std::isfinite(d)) fail(ErrorCode::Numerical, "the heat geodesic distance is not finite (t = " + format_number(geo.time()) + ")");
    dmax = std::max(dmax, d);
  }
  if (!opt.output.empty()) {
    WriteOptions wo = carried_attributes(in);
    add_result(wo, {"distance", VertexProperty::Type::Double, distance});
    add_result(wo, {"valid", VertexProperty::Type::Int, valid});
    write_mesh(opt.output, in.mesh, wo);
    log_written(opt.output);
  }
  write_preview(in.mesh, distance, PreviewKind::Scalar, go.preview,
                {"geodesic distance from vertex " + std::to_string(source),
                 {{in.mesh.x[source], in.mesh.y[source], in.mesh.z[source]}},
                 "source"});
  Json j{{"command", "geodesic"}, {"input", input_json(opt, in)}};
  j["source"] = source;
  j["method"] = "heat-full-polygon";
  j["fraction"] = go.fraction;
  j["t_factor"] = po.t_factor;
  j["t_spec"] = heat_time_text(go.time, po.t_factor);
  j["t"] = geo.time();
  j["h"] = geo.mean_edge_length();
  j["patch_size"] = n;
  j["max_distance"] = dmax;
  j["precompute_s"] = precompute_s;
  j["query_s"] = query_s;
  j["timings"] = {{"load_s", in.load_s}, {"subdivide_s", in.subdivide_s}};
  emit(opt, j, [&](std::ostream& os) {
    os << opt.mesh_path << ": heat geodesic on polygons from vertex " << source << " (t = " << geo.time()
       << ")\n  max distance " << dmax << "\n  precompute " << precompute_s << " s, query " << query_s << " s\n";
  });
  return 0;
}

int run_geodesic(const CommonOptions& opt, const GeodesicOptions& go, const RunContext& ctx) {
  if (!(go.fraction > 0 && go.fraction <= 1))
    fail(ErrorCode::BadUsage, "--fraction must be in (0, 1] (got " + format_number(go.fraction) + ")");
  const TimeSpec time = heat_time_spec(go.time, TimeSpec{HeatGeodesicOptions{}.t_factor, true});
  check_preview_options(go.preview);
  validate_factor_cache_options(go.cache);
  Input in = load_input(opt, ctx, polygon_native(go) ? PolygonFaces::Keep : PolygonFaces::Triangulate);
  const int32_t n = in.mesh.num_vertices();
  if (go.source < 0 || go.source >= n)
    fail(go.source < 0 ? ErrorCode::BadUsage : ErrorCode::BadInput, "--source " + std::to_string(go.source) + " is not a vertex of " + opt.mesh_path +
                                  " (" + std::to_string(n) + " vertices, ids 0.." + std::to_string(n - 1) + ")");
  const int32_t source = static_cast<int32_t>(go.source);
  if (!in.mesh.is_triangle_mesh()) return run_polygon_geodesic(opt, go, time, in, source, ctx);
  Stopwatch sw;
  HeatGeodesicOptions ho;
  ho.t_factor = heat_t_factor(time, time.times_h2 ? 0.0 : mean_edge_length(in.mesh));
  Factors cache_info;
  std::optional<HeatGeodesicFactors> given = heat_method_factors(go.cache, in.mesh, ho, ctx, cache_info);
  const HeatGeodesic geo = given ? HeatGeodesic(in.mesh, ho, std::move(*given)) : HeatGeodesic(in.mesh, ho, ctx);
  const double precompute_s = sw.seconds();
  ctx.check_cancel();

  // No value (outside the patch, or in another component than the source) is
  // NaN in every output, with the mask property `valid` (README "Output formats").
  std::vector<double> distance(static_cast<size_t>(n), std::numeric_limits<double>::quiet_NaN());
  std::vector<double> valid(static_cast<size_t>(n), local_fraction(go.fraction) ? 0.0 : 1.0);
  HeatGeodesicWorkspace ws;
  double query_s = 0, patch_s = 0;
  int32_t patch_size = n;
  if (local_fraction(go.fraction)) {
    const int32_t count = std::max<int32_t>(1, static_cast<int32_t>(std::lround(go.fraction * n)));
    const PatchGrower grower = prepare_patch_grower(in.mesh);  // local distances on a geodesic disk
    PatchWorkspace pws;
    std::vector<int32_t> patch;
    sw.restart();
    grow_patch_vertices(grower, source, geodesic_disk(count), pws, patch);
    patch_s = sw.seconds();
    patch_size = static_cast<int32_t>(patch.size());
    std::vector<double> d(patch.size());
    sw.restart();
    geo.query(source, patch, d, ws);
    query_s = sw.seconds();
    for (size_t k = 0; k < patch.size(); ++k) {
      distance[patch[k]] = d[k];
      valid[patch[k]] = 1;
    }
  } else {
    sw.restart();
    geo.query_full(source, distance, ws);
    query_s = sw.seconds();
  }
  // +infinity = another connected component than the source (no path): no
  // value, counted. A NaN from the solver never is an answer.
  double dmax = 0;
  int64_t unreachable = 0;
  for (size_t i = 0; i < distance.size(); ++i) {
    if (valid[i] == 0) continue;
    if (distance[i] == std::numeric_limits<double>::infinity()) {
      distance[i] = std::numeric_limits<double>::quiet_NaN();
      valid[i] = 0;
      ++unreachable;
      continue;
    }
    if (!std::isfinite(distance[i]))
      fail(ErrorCode::Numerical, "the heat geodesic distance is not finite (t = " + format_number(geo.time()) + ")");
    dmax = std::max(dmax, distance[i]);
  }

  if (!opt.output.empty()) {
    WriteOptions wo = carried_attributes(in);
    add_result(wo, {"distance", VertexProperty::Type::Double, distance});
    add_result(wo, {"valid", VertexProperty::Type::Int, valid});
    write_mesh(opt.output, output_faces(in), wo);
    log_written(opt.output);
  }
  write_preview(in.mesh, distance, PreviewKind::Scalar, go.preview,  // NaN (no value): grey
                {"geodesic distance from vertex " + std::to_string(source) +
                     (local_fraction(go.fraction) ? " (patch of " + std::to_string(patch_size) + " vertices)" : ""),
                 {{in.mesh.x[source], in.mesh.y[source], in.mesh.z[source]}},
                 "source"});
  Json j{{"command", "geodesic"}, {"input", input_json(opt, in)}};
  j["source"] = source;
  j["method"] = local_fraction(go.fraction) ? "heat-local" : "heat-full";
  j["fraction"] = go.fraction;
  j["t_factor"] = ho.t_factor;
  j["t_spec"] = heat_time_text(go.time, ho.t_factor);
  j["t"] = geo.time();
  j["h"] = geo.mean_edge_length();
  j["patch_size"] = patch_size;
  j["max_distance"] = dmax;
  j["unreachable"] = unreachable;  // vertices in other connected components (written as NaN)
  j["precompute_s"] = precompute_s;
  j["patch_s"] = patch_s;
  j["query_s"] = query_s;
  if (!go.cache.save.empty() || !go.cache.load.empty()) j["factor_cache"] = factor_cache_json(go.cache, cache_info);
  j["heat_underflow_vertices"] = ws.underflow;  // never silent: also a warning below and on stderr
  if (ws.underflow > 0) {
    const double h2 = geo.mean_edge_length() * geo.mean_edge_length();
    const std::string w = "the heat underflowed at " + std::to_string(ws.underflow) +
                          " vertices (no direction there: their distances are interpolated); --t " +
                          format_number(ws.t_no_underflow / h2) + "h2 (t = " + format_number(ws.t_no_underflow) +
                          ") avoids it";
    log("warning: " + w);
    j["t_avoiding_underflow"] = ws.t_no_underflow;
    j["warnings"] = Json::array({w});
  }
  j["timings"] = {{"load_s", in.load_s}, {"subdivide_s", in.subdivide_s}};
  emit(opt, j, [&](std::ostream& os) {
    os << opt.mesh_path << ": heat geodesic from vertex " << source << " (" << j["method"].get<std::string>()
       << ", t = " << geo.time() << ")\n  patch " << patch_size << " vertices, max distance " << dmax
       << "\n  precompute " << precompute_s << " s, query " << query_s << " s\n";
  });
  return 0;
}

}  // namespace

void register_logmap_command(CommandTable& table);  // tools/cli/cmd_logmap.cpp

// `geodesic` and `logmap` (one registration line in main.cpp for both).
void register_geodesic_commands(CommandTable& table) {
  register_logmap_command(table);
  auto go = std::make_shared<GeodesicOptions>();
  CLI::App* app = table.add("geodesic", "Heat geodesic distance from a vertex (whole mesh or localized to a patch)",
                            [go](const CommonOptions& o, const RunContext& ctx) { return run_geodesic(o, *go, ctx); });
  app->add_option("--source", go->source, "Source vertex (0-based)")->required();
  app->add_option("--fraction", go->fraction, "Patch size as a fraction of the vertices (default 1: whole mesh)");
  add_heat_time_options(app, go->time, "4h2 (polygon meshes 8h2), for accuracy; a query costs the same at any t",
                        /*factor_alias=*/true);
  add_preview_option(app, go->preview);
  add_factor_cache_options(app, go->cache);
}

}  // namespace locus::cli
