// `locus logmap MESH --center V --fraction f [--t T] [--method heat|heat-full|dem]
//  [--angle auto|log|two-ring|average] [--lattice none|star|ring|path] [--recenter on|off]
//  [--clip-injective] -o map.ply`: a log map (local polar / Cartesian
// coordinates) of the geodesic disk of round(f * n) vertices around the
// center; a client of locus::Session::logmap
// (engine/include/locus/engine/geodesic_requests.hpp), which owns the
// validation, defaults and computation. Output: per-vertex u, v (PLY
// properties u/v, OBJ vt) and the properties distance, angle (NaN outside the
// patch), valid and in_patch. JSON: the report's statistics.
#include <cmath>
#include <limits>
#include <memory>
#include <ostream>

#include "locus/engine/geodesic_requests.hpp"
#include "locus/session.hpp"
#include "tools/cli/cli_common.hpp"

namespace locus::cli {
namespace {

struct LogmapCli {
  LogmapRequest request;   // every option of the command but the common ones and the preview
  PreviewOptions preview;  // --preview out.png: checkerboard of (u, v) on the patch
};

// The map as per-vertex output (-o): outside the patch NaN in every field, 0
// in the masks `valid` and `in_patch` (the older name, kept for scripts).
void write_map(const CommonOptions& opt, const Input& in, const LogmapReport& r) {
  if (opt.output.empty()) return;
  const size_t n = static_cast<size_t>(in.mesh.num_vertices());
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<double> uv(2 * n, nan), dist(n, nan), ang(n, nan), in_patch(n, 0.0);
  for (size_t p = 0; p < r.patch.size(); ++p) {
    const size_t i = static_cast<size_t>(r.patch[p]);
    uv[2 * i] = r.u[p];
    uv[2 * i + 1] = r.v[p];
    dist[i] = r.distance[p];
    ang[i] = r.angle[p];
    in_patch[i] = 1;
  }
  WriteOptions wo = carried_attributes(in, false, /*result_uv=*/true);
  wo.uv = &uv;
  add_result(wo, {"distance", VertexProperty::Type::Double, dist});
  add_result(wo, {"angle", VertexProperty::Type::Double, ang});
  add_result(wo, {"valid", VertexProperty::Type::Int, in_patch});
  add_result(wo, {"in_patch", VertexProperty::Type::Int, in_patch});
  write_output_mesh(opt, output_faces(in), wo);
}

// The checkerboard of (u, v) on the patch (--preview).
void write_map_preview(const Input& in, const LogmapCli& lo, const LogmapReport& r) {
  if (lo.preview.path.empty()) return;
  std::vector<double> uv(2 * static_cast<size_t>(in.mesh.num_vertices()), std::numeric_limits<double>::quiet_NaN());
  for (size_t p = 0; p < r.patch.size(); ++p) {
    uv[2 * static_cast<size_t>(r.patch[p])] = r.u[p];
    uv[2 * static_cast<size_t>(r.patch[p]) + 1] = r.v[p];
  }
  const int32_t c = r.center;
  write_preview(in.mesh, uv, PreviewKind::Checker, lo.preview,
                {"log map around vertex " + std::to_string(c) + " (" + std::to_string(r.patch.size()) + " vertices)",
                 {{in.mesh.x[c], in.mesh.y[c], in.mesh.z[c]}},
                 "centre"});
}

Json logmap_json(const CommonOptions& opt, const LogmapRequest& q, const Input& in, const LogmapReport& r) {
  Json j{{"command", "logmap"}, {"input", input_json(opt, in)}};
  j["center"] = r.center;
  j["method"] = r.method;
  j["angle"] = r.angle_estimator;
  j["fraction"] = r.fraction;
  j["t_factor"] = r.t_factor;
  j["t_spec"] = r.t_spec;
  if (r.polygon) {
    j["t"] = r.t;
    j["h"] = r.h;
    j["patch_size"] = r.patch.size();
    j["max_distance"] = r.max_distance;
    j["flipped_polygons"] = r.flipped;
    j["precompute_s"] = r.precompute_s;
    j["query_s"] = r.query_s;
    return j;
  }
  if (r.heat) {
    j["t"] = r.t;
    j["h"] = r.h;
    j["sources"] = r.sources;
    j["batches"] = r.batches;  // groups of 8 lanes
    j["passes"] = r.passes;    // wide solves over the plan (0 for heat-full)
    j["two_ring"] = r.two_ring;
    j["lattice"] = q.lattice;
    j["recentre"] = q.recenter;  // JSON keys keep their released spelling
    j["recentred"] = r.recentered;
    j["angle_fallbacks"] = r.angle_fallbacks;
    j["heat_underflow_vertices"] = r.heat_underflow_vertices;  // also a warning
    if (r.heat_underflow_vertices > 0) j["t_avoiding_underflow"] = r.t_avoiding_underflow;
  }
  if (!r.warnings.empty()) j["warnings"] = r.warnings;
  j["patch_size"] = r.patch.size();
  j["max_distance"] = r.max_distance;
  j["flipped_triangles"] = r.flipped;
  // null: no triangle flipped, the whole patch is one-to-one.
  j["injectivity_radius"] = std::isfinite(r.injectivity_radius) ? Json(r.injectivity_radius) : Json(nullptr);
  j["clipped_vertices"] = r.clipped_vertices;  // --clip-injective: patch vertices dropped
  j["precompute_s"] = r.precompute_s;
  if (r.factor_cache.used()) j["factor_cache"] = factor_cache_json(r.factor_cache);
  j["patch_s"] = r.patch_s;
  j["query_s"] = r.query_s;
  j["query_threads"] = 1;  // a query runs on one thread (key kept for readers of earlier output)
  return j;
}

int run_logmap(const CommonOptions& opt, const LogmapCli& lo, const RunContext& ctx) {
  check_uv_output(opt, "logmap");
  check_request(lo.request);
  note_deprecated_t_factor(lo.request.t_factor);
  check_preview_options(lo.preview);
  const Input in = load_input(opt, ctx, keeps_polygons(lo.request) ? PolygonFaces::Keep : PolygonFaces::Triangulate);
  check_file_vertex("--center", lo.request.center, in, opt);
  const Session session{Mesh(in.mesh), session_options(in)};
  const LogmapReport r = session.logmap(lo.request, ctx);
  for (const std::string& w : r.warnings) log("warning: " + w);
  write_map(opt, in, r);
  write_map_preview(in, lo, r);
  Json j = logmap_json(opt, lo.request, in, r);
  j["timings"] = timings(in);
  emit(opt, j, [&](std::ostream& os) {
    os << opt.mesh_path << ": log map " << (r.polygon ? "on polygons " : "") << "around vertex " << r.center << " ("
       << r.method << ")\n  patch " << r.patch.size() << " vertices, max distance " << r.max_distance << ", flipped "
       << (r.polygon ? "polygons " : "triangles ") << r.flipped << "\n  precompute " << r.precompute_s
       << " s, query " << r.query_s << " s\n";
  });
  return 0;
}

}  // namespace

void register_logmap_command(CommandTable& table) {
  auto lo = std::make_shared<LogmapCli>();
  CLI::App* app = table.add("logmap", "Log map (geodesic polar coordinates) of a patch: heat, heat-full or DEM",
                            [lo](const CommonOptions& o, const RunContext& ctx) { return run_logmap(o, *lo, ctx); });
  LogmapRequest& q = lo->request;
  app->add_option("--center", q.center, "Center vertex (0-based)")->required();
  app->add_option("--fraction", q.fraction, "Patch size as a fraction of the vertices (default 0.05)");
  add_heat_method_time(app, q.t, q.t_factor,
                       "4h2 (polygon meshes 8h2), for accuracy; a query costs the same at any t");
  app->add_option("--method", q.method, "heat (localized, default), heat-full or dem");
  app->add_option("--angle", q.angle,
                  "Angle estimator of the heat map: auto (default: two-ring at irregular stars, ~3x the heat lanes "
                  "of the one-ring; average at valence != 6; log elsewhere), log, two-ring, average");
  app->add_option("--lattice", q.lattice,
                  "Lattice (dispersion) correction of the heat map's angles: none, star, ring or path (default: the "
                  "library's, path)");
  app->add_option("--recenter,--recentre", q.recenter,
                  "Recenter the heat map's gradients: on or off (default: the library's)");
  app->add_flag("--clip-injective", q.clip_injective,
                "Keep only the patch vertices closer than the injectivity radius (no flipped triangle)");
  add_preview_option(app, lo->preview);
  add_factor_cache_options(app, q.save, q.load);
}

}  // namespace locus::cli
