// `locus-bench logmap-accuracy SPEC`: the accuracy experiment of thesis §6.7
// (Table 6.8.1) on an analytic surface (analytic_surfaces.hpp).
// Patch: the vertices within geodesic distance --radius (exact) of the center.
// Errors (map_errors.hpp): E_d and E_a over the patch without the center. Heat
// (localized, both angle estimators and both Poisson right-hand sides), heat
// with full solves, and DEM; under "variants" every angle estimator x lattice
// correction x recenter (pipelines/include/locus/pipelines/geodesic/logmap.hpp)
// with the mean, the worst center and the per-center E_a. --center-ids picks
// the centers (e.g. 0,13: an icosahedron corner and an edge midpoint), --dump
// writes per-vertex values of one variant (--dump-variant).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>

#include "locus/error.hpp"
#include "locus/kernels/mesh/patch_grower.hpp"
#include "locus/kernels/parallel/thread_cpu_time.hpp"
#include "locus/mesh_io.hpp"
#include "locus/pipelines/geodesic/dem_logmap.hpp"
#include "locus/pipelines/geodesic/logmap.hpp"
#include "locus/pipelines/geodesic/polygon_heat_geodesic.hpp"
#include "locus/pipelines/geodesic/polygon_logmap.hpp"
#include "tools/bench/analytic_surfaces.hpp"
#include "tools/bench/bench_centers.hpp"
#include "tools/bench/bench_commands.hpp"
#include "tools/bench/map_errors.hpp"
#include "tools/bench/logmap_choices.hpp"

namespace locus::bench {
namespace {

using cli::Json;
using cli::Stopwatch;

struct AccuracyOptions {
  int centers = 3;
  double radius = 0.5;
  double t_factor = 0;  // 0: the library's default (triangles: HeatGeodesicOptions, polygons: PolygonHeatGeodesicOptions)
  bool no_full = false;
  bool plain_gradient = false;  // HeatGeodesicOptions::log_heat_gradient = false
  std::string dump;  // CSV of per-vertex exact and computed values of one variant
  std::string dump_variant = "log_none";
  std::string center_ids;  // explicit centers instead of random ones
  std::string lattice = "default";  // the correction of the default (Auto) rows
  std::string recenter = "default";
  double mass_blend = 0.0;
  std::string center_set = "random";  // random, or irregular: vertices of valence != 6 (--centers of them)
  std::string patch_kind = "exact";   // exact: within --radius; graph: the Dijkstra disk of as many vertices (the CLI's)
  bool quick = false;                 // the default map, full solves and DEM only (no estimator variants)
  int bands = 10;                     // radius bands of the default map's errors
  std::string save_surface;           // write the generated surface (e.g. .off) for the CLI
};

// Polygon meshes (cube-sphere:N): the polygon log map (full solves), E_d / E_a
// per center and by radius band, flipped polygons.
int run_polygon_accuracy(const cli::CommonOptions& opt, const AccuracyOptions& ao, const Surface& s,
                         const RunContext& ctx) {
  PolygonHeatGeodesicOptions po;
  if (ao.t_factor > 0) po.t_factor = ao.t_factor;
  Stopwatch sw;
  const PolygonLogMap lm(s.mesh, po, ctx);
  const double precompute_s = sw.seconds();
  const std::vector<int32_t> centers = accuracy_centers(s, ao.center_ids, ao.center_set, ao.centers, opt.seed);
  const int32_t n = s.mesh.num_vertices();
  std::vector<int32_t> valence(static_cast<size_t>(n), 0);
  for (int32_t v : s.mesh.face_vertices) ++valence[v];
  Bands bands(ao.bands);
  Json per_center = Json::array();
  double ed = 0, ea = 0, query_s = 0;
  int64_t flipped = 0;
  for (int32_t c : centers) {
    ctx.check_cancel();
    std::vector<int32_t> patch{c};
    for (int32_t j = 0; j < n; ++j)
      if (j != c && s.exact_distance(c, j) <= ao.radius) patch.push_back(j);
    Maps m;
    m.resize(patch.size());
    sw.restart();
    lm.query_full(c, patch, m.out());
    query_s += sw.seconds() / centers.size();
    const Errors e = errors_of(s, c, patch, m.d, m.a, nullptr, &bands);
    ed += e.ed / centers.size();
    ea += e.ea / centers.size();
    const int64_t f = count_flipped_polygons(s.mesh, patch, m.u, m.v);
    flipped += f;
    per_center.push_back(Json{{"center", c}, {"valence", valence[c]}, {"patch_size", patch.size()}, {"E_d", e.ed},
                              {"E_a", e.ea}, {"flipped_polygons", f}});
  }
  Json j{{"command", "logmap-accuracy"}, {"surface", opt.mesh_path}, {"polygons", true}};
  j["n"] = n;
  j["h"] = lm.geodesic().mean_edge_length();
  j["t"] = lm.geodesic().time();
  j["t_factor"] = po.t_factor;
  j["radius"] = ao.radius;
  j["centers"] = centers;
  j["heat_full_polygon"] = Json{{"E_d", ed}, {"E_a", ea}};
  j["flipped_polygons"] = flipped;
  j["per_center"] = per_center;
  j["radius_bands_full"] = bands.json();
  j["precompute_s"] = precompute_s;
  j["query_s"] = query_s;
  cli::emit(opt, j, [&](std::ostream& os) { os << j.dump(2) << "\n"; });
  return 0;
}

// Accumulated means over centers (each center's mean weighs the same) and the worst center.
struct Acc {
  double ed = 0, ea = 0, ed_worst = 0, ea_worst = 0;
  int32_t worst_center = -1;
  void add(const Errors& e, double w, int32_t c = -1) {
    ed += e.ed * w;
    ea += e.ea * w;
    ed_worst = std::max(ed_worst, e.ed);
    if (e.ea > ea_worst) ea_worst = e.ea, worst_center = c;
  }
  Json json() const {
    return Json{{"E_d", ed}, {"E_a", ea}, {"E_d_worst", ed_worst}, {"E_a_worst", ea_worst},
                {"worst_center", worst_center}};
  }
};

// Every estimator with and without the lattice correction (pipelines/include/locus/pipelines/geodesic/logmap.hpp).
struct Variant {
  std::string name;
  LogMapEstimator est;
  Acc acc;
  int64_t flipped = 0;
  Json per_center = Json::array();
  double cpu_s = 0;  // mean thread CPU time of the localized query
};

std::vector<Variant> all_variants() {
  std::vector<Variant> variants;
  for (auto [an, a] : {std::pair{"log", LogMapAngle::LogHeat}, std::pair{"two_ring", LogMapAngle::LogHeatTwoRing},
                       std::pair{"auto", LogMapAngle::Auto}})
    for (auto [ln, l] : {std::pair{"none", LatticeCorrection::None}, std::pair{"star", LatticeCorrection::Star},
                         std::pair{"ring", LatticeCorrection::Ring},
                         std::pair{"path", LatticeCorrection::Path}})
      for (bool rc : {false, true})
        variants.push_back({std::string(an) + "_" + ln + (rc ? "_recenter" : ""), {a, l, rc}, {}, 0, Json::array(), 0.0});
  return variants;
}

// The maps of one run on a triangle mesh, measured center by center and
// accumulated (every center weighs 1 / centers).
struct TriangleAccuracy {
  TriangleAccuracy(const AccuracyOptions& options, const Surface& surface, const HeatLogMap& h, const DemLogMap& d,
                   size_t centers)
      : ao(options), s(surface), heat(h), dem(d), n(surface.mesh.num_vertices()), w(1.0 / centers),
        valence(static_cast<size_t>(n), 0), bands_local(options.bands), bands_full(options.bands),
        dem_patch(n), dem_pos(n, -1), du(n), dv(n) {
    for (int32_t f = 0; f < s.mesh.num_faces(); ++f) ++valence[s.mesh.f0[f]], ++valence[s.mesh.f1[f]], ++valence[s.mesh.f2[f]];
  }

  void measure(int32_t c, const std::vector<int32_t>& patch, bool first_center);
  void measure_variants(int32_t c, const std::vector<int32_t>& patch, Maps& m, bool first_center);
  void measure_default(int32_t c, const std::vector<int32_t>& patch, Maps& m);
  void measure_full(int32_t c, const std::vector<int32_t>& patch);
  void measure_dem(int32_t c, const std::vector<int32_t>& patch);
  int64_t flips(std::span<const int32_t> patch, std::span<const double> u, std::span<const double> v) {
    return count_flipped_triangles(heat.geodesic().gradients(), patch, u, v, scratch);
  }
  void report(Json& j) const;

  const AccuracyOptions& ao;
  const Surface& s;
  const HeatLogMap& heat;
  const DemLogMap& dem;
  const int32_t n;
  const double w;
  std::vector<int32_t> valence;
  Bands bands_local, bands_full;
  Json per_center = Json::array();
  Acc log_flux, plain_flux, two_ring, auto_acc, log_trunc, full_log, full_plain, dem_acc;
  std::vector<Variant> variants = all_variants();
  int64_t flipped_heat = 0, flipped_two_ring = 0, flipped_auto = 0, auto_two_ring = 0, flipped_full = 0, flipped_dem = 0,
          fallbacks = 0, patch_total = 0;
  double local_vs_full_d = 0;
  LogMapWorkspace lws;
  DemWorkspace dws;
  std::vector<int32_t> scratch, dem_patch, dem_pos;
  std::vector<double> du, dv;
};

void TriangleAccuracy::measure(int32_t c, const std::vector<int32_t>& patch, bool first_center) {
  patch_total += static_cast<int64_t>(patch.size());
  Maps m;
  m.resize(patch.size());
  measure_variants(c, patch, m, first_center);
  measure_default(c, patch, m);
  if (!ao.no_full) measure_full(c, patch);
  measure_dem(c, patch);
}

// Every estimator variant (unless --quick), and the --dump of one of them.
void TriangleAccuracy::measure_variants(int32_t c, const std::vector<int32_t>& patch, Maps& m, bool first_center) {
  for (Variant& v : variants) {
    if (ao.quick) break;
    const double c0 = thread_cpu_seconds();
    heat.query(c, patch, m.out(), lws, v.est);
    v.cpu_s += (thread_cpu_seconds() - c0) * w;
    const Errors e = errors_of(s, c, patch, m.d, m.a);
    v.acc.add(e, w, c);
    v.per_center.push_back(e.ea);
    v.flipped += flips(patch, m.u, m.v);
    if (!ao.dump.empty() && v.name == ao.dump_variant) {
      std::FILE* fp = std::fopen(ao.dump.c_str(), first_center ? "w" : "a");
      if (!fp) fail(ErrorCode::BadUsage, "cannot write " + ao.dump);
      for (size_t p = 0; p < patch.size(); ++p)
        std::fprintf(fp, "%d,%d,%.9g,%.9g,%.9g,%.9g\n", c, patch[p], s.exact_distance(c, patch[p]),
                     exact_angle(s, c, patch[p]), m.d[p], m.a[p]);
      std::fclose(fp);
    }
  }
}

// The localized map with each angle estimator, and the truncated Poisson right-hand side.
void TriangleAccuracy::measure_default(int32_t c, const std::vector<int32_t>& patch, Maps& m) {
  LogMapStats st = heat.query(c, patch, m.out(), lws, LogMapEstimator{LogMapAngle::LogHeat, LatticeCorrection::None, false});
  fallbacks += st.angle_fallbacks;
  log_flux.add(errors_of(s, c, patch, m.d, m.a), w, c);
  flipped_heat += flips(patch, m.u, m.v);
  heat.query(c, patch, m.out(), lws, LogMapAngle::HeatAverage);
  plain_flux.add(errors_of(s, c, patch, m.d, m.a), w, c);
  st = heat.query(c, patch, m.out(), lws, LogMapAngle::Auto);
  const Errors ea = errors_of(s, c, patch, m.d, m.a, nullptr, &bands_local);
  auto_acc.add(ea, w, c);
  {
    Bands own(ao.bands);
    errors_of(s, c, patch, m.d, m.a, nullptr, &own);
    per_center.push_back(Json{{"center", c}, {"valence", valence[c]}, {"patch_size", patch.size()},
                              {"two_ring", st.two_ring}, {"E_d", ea.ed}, {"E_a", ea.ea},
                              {"E_d_outer_band", own.mean_ed(ao.bands - 1, ao.bands)},
                              {"E_d_inner_half", own.mean_ed(0, ao.bands / 2)}});
  }
  auto_two_ring += st.two_ring;
  flipped_auto += flips(patch, m.u, m.v);
  heat.query(c, patch, m.out(), lws, LogMapAngle::LogHeatTwoRing);
  two_ring.add(errors_of(s, c, patch, m.d, m.a), w, c);
  flipped_two_ring += flips(patch, m.u, m.v);
  // Truncated Poisson right-hand side (distance only; the angle does not depend on it).
  HeatGeodesicWorkspace gws;
  std::vector<double> dt(patch.size());
  heat.geodesic().query(c, patch, dt, gws, HeatGeodesicOptions::PoissonRhs::Truncated);
  log_trunc.add(errors_of(s, c, patch, dt, m.a), w);
}

// The map with full solves, and its distance from the localized one.
void TriangleAccuracy::measure_full(int32_t c, const std::vector<int32_t>& patch) {
  Maps f;
  f.resize(patch.size());
  heat.query_full(c, patch, f.out(), lws, LogMapAngle::Auto);
  errors_of(s, c, patch, f.d, f.a, nullptr, &bands_full);
  heat.query_full(c, patch, f.out(), lws, LogMapAngle::HeatAverage);
  full_plain.add(errors_of(s, c, patch, f.d, f.a), w, c);
  heat.query_full(c, patch, f.out(), lws, LogMapEstimator{LogMapAngle::LogHeat, LatticeCorrection::None, false});
  full_log.add(errors_of(s, c, patch, f.d, f.a), w, c);
  flipped_full += flips(patch, f.u, f.v);
  Maps l2;
  l2.resize(patch.size());
  heat.query(c, patch, l2.out(), lws, LogMapEstimator{LogMapAngle::LogHeat, LatticeCorrection::None, false});
  double md = 0;
  for (size_t p = 0; p < patch.size(); ++p) md = std::max(md, std::abs(l2.d[p] - f.d[p]));
  local_vs_full_d = std::max(local_vs_full_d, md);
}

// DEM over a graph-metric disk comfortably containing the exact one.
void TriangleAccuracy::measure_dem(int32_t c, const std::vector<int32_t>& patch) {
  const int32_t kd = dem.query(c, n, 1.5 * ao.radius, dem_patch, du, dv, dws);
  for (int32_t p = 0; p < kd; ++p) dem_pos[dem_patch[p]] = p;
  std::vector<double> dd(patch.size()), da(patch.size());
  std::vector<uint8_t> mapped(patch.size(), 0);
  for (size_t p = 0; p < patch.size(); ++p) {
    const int32_t q = dem_pos[patch[p]];
    if (q < 0) continue;
    mapped[p] = 1;
    dd[p] = std::hypot(du[q], dv[q]);
    da[p] = std::atan2(dv[q], du[q]);
  }
  dem_acc.add(errors_of(s, c, patch, dd, da, &mapped), w, c);
  flipped_dem += flips(std::span<const int32_t>(dem_patch.data(), kd), std::span<const double>(du.data(), kd),
                       std::span<const double>(dv.data(), kd));
  for (int32_t p = 0; p < kd; ++p) dem_pos[dem_patch[p]] = -1;
}

// The accumulated errors, in the report's order after its header fields.
void TriangleAccuracy::report(Json& j) const {
  j["heat_local_logheat"] = log_flux.json();
  j["heat_local_heataverage"] = plain_flux.json();
  j["heat_local_auto"] = auto_acc.json();
  j["auto_two_ring_centers"] = auto_two_ring;
  j["flipped_triangles_heat_auto"] = flipped_auto;
  j["heat_local_logheat_tworing"] = two_ring.json();
  j["flipped_triangles_heat_tworing"] = flipped_two_ring;
  j["heat_local_truncated_rhs_distance"] = log_trunc.ed;
  if (!ao.no_full) {
    j["heat_full_logheat"] = full_log.json();
    j["heat_full_heataverage"] = full_plain.json();
    j["local_vs_full_distance_max"] = local_vs_full_d;
    j["flipped_triangles_heat_full"] = flipped_full;
  }
  j["dem"] = dem_acc.json();
  j["lattice_correction"] = ao.lattice;
  Json var = Json::object();
  for (const Variant& v : variants) {
    Json e = v.acc.json();
    e["flipped_triangles"] = v.flipped;
    e["E_a_per_center"] = v.per_center;
    e["query_cpu_s"] = v.cpu_s;
    var[v.name] = e;
  }
  j["variants"] = var;
  j["center_set"] = ao.center_set;
  j["patch"] = ao.patch_kind;
  j["per_center"] = per_center;  // the default map (heat_local_auto)
  j["radius_bands_local"] = bands_local.json();
  if (!ao.no_full) j["radius_bands_full"] = bands_full.json();
  j["flipped_triangles_heat"] = flipped_heat;
  j["flipped_triangles_dem"] = flipped_dem;
  j["angle_fallbacks"] = fallbacks;
}

int run_accuracy(const cli::CommonOptions& opt, const AccuracyOptions& ao, const RunContext& ctx) {
  Stopwatch sw;
  const Surface s = make_surface(opt.mesh_path);
  if (!s.mesh.is_triangle_mesh()) return run_polygon_accuracy(opt, ao, s, ctx);
  const double generate_s = sw.seconds();
  const int32_t n = s.mesh.num_vertices();
  sw.restart();
  LogMapOptions lo;
  if (ao.t_factor > 0) lo.geodesic.t_factor = ao.t_factor;
  lo.geodesic.log_heat_gradient = !ao.plain_gradient;
  if (const auto l = cli::parse_logmap_lattice(ao.lattice)) lo.lattice = *l;
  if (const auto r = cli::parse_logmap_recenter(ao.recenter)) lo.recenter = *r;
  lo.geodesic.mass_blend = ao.mass_blend;
  const HeatLogMap heat(s.mesh, lo, ctx);
  const double precompute_s = sw.seconds();
  const DemLogMap dem(s.mesh);
  const std::vector<int32_t> centers = accuracy_centers(s, ao.center_ids, ao.center_set, ao.centers, opt.seed);
  if (ao.patch_kind != "exact" && ao.patch_kind != "graph") fail(ErrorCode::BadUsage, "--patch must be exact or graph");
  if (ao.bands < 2 || ao.bands > 100) fail(ErrorCode::BadUsage, "--bands must be in 2..100");
  if (!ao.save_surface.empty()) write_mesh(ao.save_surface, s.mesh);
  const PatchGrower grower = ao.patch_kind == "graph" ? prepare_patch_grower(s.mesh) : PatchGrower{};
  PatchWorkspace pws;
  TriangleAccuracy run(ao, s, heat, dem, centers.size());
  for (int32_t c : centers) {
    ctx.check_cancel();
    std::vector<int32_t> patch{c};
    for (int32_t j = 0; j < n; ++j)
      if (j != c && s.exact_distance(c, j) <= ao.radius) patch.push_back(j);
    if (ao.patch_kind == "graph")  // the CLI's patch: a Dijkstra disk of as many vertices
      grow_patch_vertices(grower, c, geodesic_disk(static_cast<int32_t>(patch.size())), pws, patch);
    run.measure(c, patch, c == centers.front());
  }
  Json j{{"command", "logmap-accuracy"}, {"surface", opt.mesh_path}};
  j["n"] = n;
  j["h"] = heat.geodesic().mean_edge_length();
  j["t_factor"] = lo.geodesic.t_factor;
  j["mass_blend"] = ao.mass_blend;
  j["distance_gradient"] = ao.plain_gradient ? "heat" : "log_heat";
  j["radius"] = ao.radius;
  j["centers"] = centers;
  j["mean_patch_size"] = static_cast<double>(run.patch_total) / centers.size();
  j["generate_s"] = generate_s;
  j["precompute_s"] = precompute_s;
  run.report(j);
  cli::emit(opt, j, [&](std::ostream& os) { os << j.dump(2) << "\n"; });
  return 0;
}

}  // namespace

void register_logmap_accuracy_bench(cli::CommandTable& table) {
  auto ao = std::make_shared<AccuracyOptions>();
  CLI::App* acc = table.add(
      "logmap-accuracy",
      "E_d / E_a against analytic maps; mesh-file is a surface spec: icosphere:L, random-sphere:N or bump:RINGS",
      [ao](const cli::CommonOptions& o, const RunContext& ctx) { return run_accuracy(o, *ao, ctx); });
  acc->add_option("--centers", ao->centers, "Random centers (spheres; the bump uses its top), default 3");
  acc->add_option("--radius", ao->radius, "Geodesic radius of the patch, default 0.5");
  acc->add_option("--t-factor", ao->t_factor, "t = c h^2 (default: the library's, 4 for triangles, 8 for polygon meshes)");
  acc->add_flag("--no-full", ao->no_full, "Skip the full-solve variant");
  acc->add_flag("--plain-gradient", ao->plain_gradient, "Distance from grad h (Crane et al.) instead of grad log h");
  acc->add_option("--center-ids", ao->center_ids, "Comma-separated center vertices instead of random ones");
  acc->add_option("--lattice", ao->lattice, "Lattice correction of the unnamed rows: none, star, ring, path (default: the library's)");
  acc->add_option("--recenter,--recentre", ao->recenter, "Recenter the gradients in the unnamed rows: on, off (default: the library's)");
  acc->add_option("--mass-blend", ao->mass_blend, "Heat operator mass: (1 - b) lumped + b consistent (default 0)");
  acc->add_option("--dump", ao->dump, "CSV of per-vertex exact and computed (distance, angle) of --dump-variant");
  acc->add_option("--dump-variant", ao->dump_variant, "Variant written by --dump (default log_none; see 'variants')");
  acc->add_option("--center-set", ao->center_set,
                  "random (default) or irregular: --centers vertices of valence != 6 (icospheres: the 12 corners)");
  acc->add_option("--patch", ao->patch_kind,
                  "exact (default): the vertices within --radius; graph: the Dijkstra disk of as many vertices (the CLI's)");
  acc->add_flag("--quick", ao->quick, "Only the default map, full solves and DEM (no estimator variants)");
  acc->add_option("--bands", ao->bands, "Radius bands of the default map's errors (default 10)");
  acc->add_option("--save-surface", ao->save_surface, "Write the generated surface to this file (.off, .ply, .obj)");
}

}  // namespace locus::bench
