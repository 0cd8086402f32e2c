// `locus logmap MESH --center V --fraction f [--t T] [--method heat|dem|heat-full]
//  [--angle auto|log|two-ring|average] [--lattice none|star|ring|path] [--recenter on|off] -o map.ply`: a log map (local polar /
// Cartesian coordinates) of the geodesic disk of round(f * n) vertices around
// the center. heat: thesis §6.5-6.6 with exact subset solves
// (pipelines/include/locus/pipelines/geodesic/logmap.hpp); heat-full: the same with full solves; dem: the
// Dijkstra-based discrete exponential map (pipelines/include/locus/pipelines/geodesic/dem_logmap.hpp).
// Output: per-vertex u, v (PLY properties u/v, OBJ vt; 0 outside the patch) and
// PLY properties distance, angle (-1 and 0 outside) and in_patch. JSON:
// precompute_s, query_s, patch_size, flipped_triangles, injectivity_radius
// (--clip-injective keeps the patch inside it), heat underflow warnings, and the
// solve sizes. Polygon meshes: the polygon log map with full solves
// (pipelines/include/locus/pipelines/geodesic/polygon_logmap.hpp).
#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>
#include <ostream>

#include "locus/error.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/kernels/mesh/patch_grower.hpp"
#include "locus/kernels/mesh/polygon_triangulation.hpp"
#include "locus/mesh_io.hpp"
#include "locus/pipelines/geodesic/dem_logmap.hpp"
#include "locus/pipelines/geodesic/logmap.hpp"
#include "locus/pipelines/geodesic/polygon_logmap.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "tools/cli/cli_common.hpp"
#include "tools/cli/written_files.hpp"
#include "tools/cli/heat_method_cache.hpp"
#include "tools/cli/logmap_choices.hpp"

namespace locus::cli {
namespace {

struct LogmapOptions {
  int64_t center = -1;
  double fraction = 0.05;
  HeatTimeOptions time;  // --t (default 4h2, polygon meshes 8h2), --t-factor (deprecated)
  std::string method = "heat";
  std::string angle = "auto";
  std::string lattice = "default";  // library default (LogMapOptions::lattice)
  std::string recenter = "default";  // on, off or the library default (LogMapOptions::recenter)
  PreviewOptions preview;  // --preview out.png: checkerboard of (u, v) on the patch
  bool clip_injective = false;  // drop the patch vertices at or beyond the injectivity radius
  FactorCacheOptions cache;
  bool t_given() const { return !time.t_text.empty() || !time.t_factor.empty(); }  // else each mesh kind's default
};

// Flipped triangles and the injectivity radius (the largest radius with no
// flipped triangle; infinite: none flipped); with `clip`, the patch and its
// values shrunk to the vertices inside it, and the flips counted again.
struct Injectivity {
  int64_t flipped = 0;
  double radius = 0;
  int32_t clipped = 0;
};
Injectivity injectivity(const Mesh& mesh, bool clip, std::vector<int32_t>& patch, std::vector<double>& d,
                        std::vector<double>& a, std::vector<double>& u, std::vector<double>& v) {
  const TriangleGradients tg = triangle_gradients(mesh);
  std::vector<int32_t> scratch;
  Injectivity r;
  r.flipped = count_flipped_triangles(tg, patch, u, v, scratch);
  r.radius = injectivity_radius(tg, patch, u, v, d, scratch);
  if (!clip || !std::isfinite(r.radius)) return r;
  size_t w = 0;
  for (size_t p = 0; p < patch.size(); ++p)
    if (d[p] < r.radius) patch[w] = patch[p], d[w] = d[p], a[w] = a[p], u[w] = u[p], v[w] = v[p], ++w;
  r.clipped = static_cast<int32_t>(patch.size() - w);
  for (auto* x : {&d, &a, &u, &v}) x->resize(w);
  patch.resize(w);
  r.flipped = count_flipped_triangles(tg, patch, u, v, scratch);
  return r;
}

// The map as per-vertex output (-o): outside the patch NaN in every field, 0
// in the masks `valid` and `in_patch` (the older name, kept for scripts).
void write_map(const CommonOptions& opt, const Input& in, std::span<const int32_t> patch, std::span<const double> d,
               std::span<const double> a, std::span<const double> u, std::span<const double> v) {
  if (opt.output.empty()) return;
  const size_t n = static_cast<size_t>(in.mesh.num_vertices());
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<double> uv(2 * n, nan), dist(n, nan), ang(n, nan), in_patch(n, 0.0);
  for (size_t p = 0; p < patch.size(); ++p) {
    const size_t i = static_cast<size_t>(patch[p]);
    uv[2 * i] = u[p];
    uv[2 * i + 1] = v[p];
    dist[i] = d[p];
    ang[i] = a[p];
    in_patch[i] = 1;
  }
  WriteOptions wo = carried_attributes(in, false, /*result_uv=*/true);
  wo.uv = &uv;
  add_result(wo, {"distance", VertexProperty::Type::Double, dist});
  add_result(wo, {"angle", VertexProperty::Type::Double, ang});
  add_result(wo, {"valid", VertexProperty::Type::Int, in_patch});
  add_result(wo, {"in_patch", VertexProperty::Type::Int, in_patch});
  write_mesh(opt.output, output_faces(in), wo);
  log_written(opt.output);
}

// The checkerboard of (u, v) on the patch (--preview).
void write_map_preview(const Input& in, const LogmapOptions& lo, int32_t center, std::span<const int32_t> patch,
                       std::span<const double> u, std::span<const double> v) {
  if (lo.preview.path.empty()) return;
  std::vector<double> uv(2 * static_cast<size_t>(in.mesh.num_vertices()), std::numeric_limits<double>::quiet_NaN());
  for (size_t p = 0; p < patch.size(); ++p) {
    uv[2 * static_cast<size_t>(patch[p])] = u[p];
    uv[2 * static_cast<size_t>(patch[p]) + 1] = v[p];
  }
  write_preview(in.mesh, uv, PreviewKind::Checker, lo.preview,
                {"log map around vertex " + std::to_string(center) + " (" + std::to_string(patch.size()) + " vertices)",
                 {{in.mesh.x[center], in.mesh.y[center], in.mesh.z[center]}},
                 "centre"});
}

// Polygon meshes (quads, mixed, n-gons): the heat log map on the polygon
// operators with full solves (pipelines/include/locus/pipelines/geodesic/polygon_logmap.hpp);
// the patch is the Dijkstra disk over the polygon edges. Returns the JSON's
// method-specific part; the caller writes the outputs.
struct PolygonMap {
  std::vector<int32_t> patch;
  std::vector<double> d, a, u, v;
  double precompute_s = 0, query_s = 0, t = 0, h = 0, t_factor = 0;
};
PolygonMap polygon_logmap(const Mesh& mesh, int32_t center, int32_t count, const LogmapOptions& lo, double t_factor,
                          const RunContext& ctx) {
  if (lo.method == "dem") fail(ErrorCode::BadUsage, "--method dem needs a triangle mesh (the input has polygon faces)");
  if (!lo.cache.save.empty() || !lo.cache.load.empty())
    fail(ErrorCode::BadUsage, "--save/--load need a triangle mesh (the input has polygon faces)");
  (void)triangulate_polygons(mesh, mesh.source);  // simple polygons (as cmd_geodesic.cpp says why)
  PolygonMap r;
  Stopwatch sw;
  PolygonHeatGeodesicOptions po;  // t_factor 8 unless given (see polygon_heat_geodesic.hpp)
  if (lo.t_given()) po.t_factor = t_factor;
  const PolygonLogMap map(mesh, po, ctx);
  r.precompute_s = sw.seconds();
  const Adjacency adj = vertex_adjacency(mesh);
  const HostVector<double> len = adjacency_edge_lengths(mesh, adj);
  GrowWorkspace gws;
  const GrowSeed seed{center, 0.0};
  grow_vertices(adj, len, std::span<const GrowSeed>(&seed, 1), geodesic_disk(count), gws, r.patch);
  const size_t k = r.patch.size();
  r.d.resize(k), r.a.resize(k), r.u.resize(k), r.v.resize(k);
  sw.restart();
  map.query_full(center, r.patch, {r.d, r.a, r.u, r.v});
  r.query_s = sw.seconds();
  r.t = map.geodesic().time();
  r.h = map.geodesic().mean_edge_length();
  r.t_factor = po.t_factor;
  return r;
}

int write_polygon_logmap(const CommonOptions& opt, const LogmapOptions& lo, const Input& in, int32_t center,
                         const PolygonMap& r) {
  const size_t k = r.patch.size();
  for (size_t p = 0; p < k; ++p)
    if (!std::isfinite(r.u[p]) || !std::isfinite(r.v[p]))
      fail(ErrorCode::Numerical, "the log map is not finite at vertex " + std::to_string(r.patch[p]));
  const int64_t flipped = count_flipped_polygons(in.mesh, r.patch, r.u, r.v);
  write_map(opt, in, r.patch, r.d, r.a, r.u, r.v);
  write_map_preview(in, lo, center, r.patch, r.u, r.v);
  double dmax = 0;
  for (double x : r.d) dmax = std::max(dmax, x);
  Json j{{"command", "logmap"}, {"input", input_json(opt, in)}};
  j["center"] = center;
  j["method"] = "heat-full-polygon";
  j["angle"] = "log";
  j["fraction"] = lo.fraction;
  j["t_factor"] = r.t_factor;
  j["t_spec"] = heat_time_text(lo.time, r.t_factor);
  j["t"] = r.t;
  j["h"] = r.h;
  j["patch_size"] = k;
  j["max_distance"] = dmax;
  j["flipped_polygons"] = flipped;
  j["precompute_s"] = r.precompute_s;
  j["query_s"] = r.query_s;
  emit(opt, j, [&](std::ostream& os) {
    os << opt.mesh_path << ": log map on polygons around vertex " << center << "\n  patch " << k
       << " vertices, max distance " << dmax << ", flipped polygons " << flipped << "\n  precompute "
       << r.precompute_s << " s, query " << r.query_s << " s\n";
  });
  return 0;
}

int run_logmap(const CommonOptions& opt, const LogmapOptions& lo, const RunContext& ctx) {
  check_uv_output(opt, "logmap");
  if (!(lo.fraction > 0 && lo.fraction <= 1))
    fail(ErrorCode::BadUsage, "--fraction must be in (0, 1] (got " + format_number(lo.fraction) + ")");
  const TimeSpec time = heat_time_spec(lo.time, TimeSpec{HeatGeodesicOptions{}.t_factor, true});
  const LogMapAngle angle = parse_logmap_angle(lo.angle);
  const std::optional<LatticeCorrection> lattice = parse_logmap_lattice(lo.lattice);
  const std::optional<bool> recenter = parse_logmap_recenter(lo.recenter);
  if (lo.method != "heat" && lo.method != "heat-full" && lo.method != "dem")
    fail(ErrorCode::BadUsage, "--method must be heat, heat-full or dem (got '" + lo.method + "')");
  check_preview_options(lo.preview);
  validate_factor_cache_options(lo.cache);
  if (lo.method == "dem" && (!lo.cache.save.empty() || !lo.cache.load.empty()))
    fail(ErrorCode::BadUsage, "--save/--load: the dem method factors nothing");
  // Polygons keep their faces for the polygon log map (full solves, no cache);
  // the DEM and factor caches need triangles: triangulated on load.
  const bool polygon_native = lo.method != "dem" && lo.cache.save.empty() && lo.cache.load.empty();
  Input in = load_input(opt, ctx, polygon_native ? PolygonFaces::Keep : PolygonFaces::Triangulate);
  const int32_t n = in.mesh.num_vertices();
  if (lo.center < 0 || lo.center >= n)
    fail(lo.center < 0 ? ErrorCode::BadUsage : ErrorCode::BadInput, "--center " + std::to_string(lo.center) + " is not a vertex of " + opt.mesh_path + " (" +
                                  std::to_string(n) + " vertices, ids 0.." + std::to_string(n - 1) + ")");
  const int32_t center = static_cast<int32_t>(lo.center);
  const double t_factor = heat_t_factor(time, time.times_h2 ? 0.0 : mean_edge_length(in.mesh));
  const int32_t count = std::max<int32_t>(1, static_cast<int32_t>(std::lround(lo.fraction * n)));
  if (!in.mesh.is_triangle_mesh())
    return write_polygon_logmap(opt, lo, in, center, polygon_logmap(in.mesh, center, count, lo, t_factor, ctx));

  Stopwatch sw;
  // The DEM is a method of its own (a baseline); the heat methods' patches are
  // geodesic disks of the patch grower (the same vertices, in the same order).
  std::optional<DemLogMap> dem;
  PatchGrower grower;
  if (lo.method == "dem")
    dem.emplace(in.mesh);
  else
    grower = prepare_patch_grower(in.mesh);
  double precompute_s = sw.seconds();
  std::unique_ptr<HeatLogMap> heat;
  Factors cache_info;
  if (lo.method != "dem") {
    sw.restart();
    LogMapOptions mo;
    mo.geodesic.t_factor = t_factor;
    mo.angle = angle;
    if (lattice) mo.lattice = *lattice;
    if (recenter) mo.recenter = *recenter;
    std::optional<HeatGeodesicFactors> given = heat_method_factors(lo.cache, in.mesh, mo.geodesic, ctx, cache_info);
    heat = given ? std::make_unique<HeatLogMap>(in.mesh, mo, std::move(*given))
                 : std::make_unique<HeatLogMap>(in.mesh, mo, ctx);
    precompute_s = sw.seconds();  // the heat map's own preparation (DEM's is reported apart)
  }
  ctx.check_cancel();

  DemWorkspace dws;
  PatchWorkspace pws;
  std::vector<int32_t> patch(static_cast<size_t>(count));
  std::vector<double> d, a, u, v;
  LogMapStats st;
  double query_s = 0, patch_s = 0;
  int32_t k = 0;
  if (lo.method == "dem") {
    u.resize(static_cast<size_t>(count));
    v.resize(static_cast<size_t>(count));
    sw.restart();
    k = dem->query(center, count, std::numeric_limits<double>::infinity(), patch, u, v, dws);
    query_s = sw.seconds();
    u.resize(static_cast<size_t>(k));
    v.resize(static_cast<size_t>(k));
    for (int32_t p = 0; p < k; ++p) {
      d.push_back(std::hypot(u[p], v[p]));
      a.push_back(std::atan2(v[p], u[p]));
    }
  } else {
    sw.restart();
    grow_patch_vertices(grower, center, geodesic_disk(count), pws, patch);
    k = static_cast<int32_t>(patch.size());
    patch_s = sw.seconds();
    d.resize(static_cast<size_t>(k));
    a.resize(static_cast<size_t>(k));
    u.resize(static_cast<size_t>(k));
    v.resize(static_cast<size_t>(k));
    const std::span<const int32_t> P(patch.data(), static_cast<size_t>(k));
    LogMapWorkspace ws;
    sw.restart();
    st = lo.method == "heat" ? heat->query(center, P, {d, a, u, v}, ws) : heat->query_full(center, P, {d, a, u, v}, ws);
    query_s = sw.seconds();
  }
  patch.resize(static_cast<size_t>(k));
  for (int32_t p = 0; p < k; ++p)
    if (!std::isfinite(u[p]) || !std::isfinite(v[p]))
      fail(ErrorCode::Numerical, "the log map is not finite at vertex " + std::to_string(patch[p]) +
                                     (st.underflow > 0 ? "; the heat underflowed at " + std::to_string(st.underflow) +
                                                             " patch vertices: t = " + format_number(st.t_no_underflow) +
                                                             " avoids it"
                                                       : std::string()));
  const Injectivity inj = injectivity(in.mesh, lo.clip_injective, patch, d, a, u, v);
  const int64_t flipped = inj.flipped;
  const double injective_r = inj.radius;
  const int32_t clipped = inj.clipped;
  k = static_cast<int32_t>(patch.size());

  write_map(opt, in, patch, d, a, u, v);
  write_map_preview(in, lo, center, patch, u, v);
  double dmax = 0;
  for (double x : d) dmax = std::max(dmax, x);
  Json j{{"command", "logmap"}, {"input", input_json(opt, in)}};
  j["center"] = center;
  j["method"] = lo.method;
  j["angle"] = lo.method == "dem" ? "dem" : lo.angle;
  j["fraction"] = lo.fraction;
  j["t_factor"] = t_factor;
  j["t_spec"] = heat_time_text(lo.time, t_factor);
  if (heat) {
    j["t"] = heat->geodesic().time();
    j["h"] = heat->geodesic().mean_edge_length();
    j["sources"] = st.sources;
    j["batches"] = st.batches;  // groups of 8 lanes
    j["passes"] = st.passes;    // wide solves over the plan (0 for heat-full)
    j["two_ring"] = st.two_ring;
    j["lattice"] = lo.lattice;
    j["recentre"] = lo.recenter;  // JSON keys keep their released spelling
    j["recentred"] = st.recentered;
    j["angle_fallbacks"] = st.angle_fallbacks;
    j["heat_underflow_vertices"] = st.underflow;  // never silent: also a warning below and on stderr
    if (st.underflow > 0) {
      const double h2 = heat->geodesic().mean_edge_length() * heat->geodesic().mean_edge_length();
      const std::string w = "the heat underflowed at " + std::to_string(st.underflow) +
                            " patch vertices (no direction there: distances interpolated, angles unreliable); "
                            "--t " + format_number(st.t_no_underflow / h2) + "h2 (t = " +
                            format_number(st.t_no_underflow) + ") avoids it";
      log("warning: " + w);
      j["t_avoiding_underflow"] = st.t_no_underflow;
      j["warnings"] = Json::array({w});
    }
  }
  j["patch_size"] = k;
  j["max_distance"] = dmax;
  j["flipped_triangles"] = flipped;
  // null: no triangle flipped, the whole patch is one-to-one.
  j["injectivity_radius"] = std::isfinite(injective_r) ? Json(injective_r) : Json(nullptr);
  j["clipped_vertices"] = clipped;  // --clip-injective: patch vertices dropped
  j["precompute_s"] = precompute_s;
  if (!lo.cache.save.empty() || !lo.cache.load.empty()) j["factor_cache"] = factor_cache_json(lo.cache, cache_info);
  j["patch_s"] = patch_s;
  j["query_s"] = query_s;
  j["query_threads"] = 1;  // a query runs on one thread (key kept for readers of earlier output)
  j["timings"] = {{"load_s", in.load_s}, {"subdivide_s", in.subdivide_s}};
  emit(opt, j, [&](std::ostream& os) {
    os << opt.mesh_path << ": log map around vertex " << center << " (" << lo.method << ")\n  patch " << k
       << " vertices, max distance " << dmax << ", flipped triangles " << flipped << "\n  precompute "
       << precompute_s << " s, query " << query_s << " s\n";
  });
  return 0;
}

}  // namespace

void register_logmap_command(CommandTable& table) {
  auto lo = std::make_shared<LogmapOptions>();
  CLI::App* app = table.add("logmap", "Log map (geodesic polar coordinates) of a patch: heat, heat-full or DEM",
                            [lo](const CommonOptions& o, const RunContext& ctx) { return run_logmap(o, *lo, ctx); });
  app->add_option("--center", lo->center, "Center vertex (0-based)")->required();
  app->add_option("--fraction", lo->fraction, "Patch size as a fraction of the vertices (default 0.05)");
  add_heat_time_options(app, lo->time, "4h2 (polygon meshes 8h2), for accuracy; a query costs the same at any t",
                        /*factor_alias=*/true);
  app->add_option("--method", lo->method, "heat (localized, default), heat-full or dem");
  app->add_option("--angle", lo->angle, "Angle estimator of the heat map: auto (default: two-ring at irregular stars, ~3x the heat lanes of the one-ring; average at valence != 6; log elsewhere), log, two-ring, average");
  app->add_option("--lattice", lo->lattice,
                  "Lattice (dispersion) correction of the heat map's angles: none, star, ring or path (default: the library's, path)");
  app->add_option("--recenter,--recentre", lo->recenter,
                  "Recenter the heat map's gradients: on or off (default: the library's)");
  app->add_flag("--clip-injective", lo->clip_injective,
                "Keep only the patch vertices closer than the injectivity radius (no flipped triangle)");
  add_preview_option(app, lo->preview);
  add_factor_cache_options(app, lo->cache);
}

}  // namespace locus::cli
