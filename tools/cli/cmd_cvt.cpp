// `locus cvt MESH`: centroidal Voronoi tessellation by Lloyd's method with heat
// cells and centroids (thesis §3.7.1; pipelines/include/locus/pipelines/voronoi/cvt_lloyd.hpp), localized
// (approximate selective solves, default) or with full solves (--solver full, for
// comparison), isotropic or anisotropic (--anisotropy lambda). -o writes the
// remesh: the restricted-Delaunay dual of the final cells, repaired into a
// manifold with the input's topology (pipelines/.../voronoi/cvt_remesh.hpp);
// --labels writes the input with a per-vertex `label` property (the cell),
// --sites-out the sites; --json reports the timings, the `remesh` object
// (remesh_quality.hpp) and the quality of the cells (cvt_quality.hpp).
#include <functional>
#include <memory>
#include <mutex>
#include <ostream>
#include <string>
#include <vector>

#include "locus/error.hpp"
#include "locus/kernels/heat/heat_diffusion.hpp"
#include "locus/kernels/heat/surface_point.hpp"
#include "locus/mesh_io.hpp"
#include "locus/pipelines/voronoi/cvt_lloyd.hpp"
#include "locus/pipelines/voronoi/cvt_quality.hpp"
#include "locus/pipelines/voronoi/cvt_remesh.hpp"
#include "locus/pipelines/voronoi/remesh_quality.hpp"
#include "locus/kernels/mesh/mesh_derived.hpp"
#include "tools/cli/cli_common.hpp"
#include "tools/cli/written_files.hpp"
#include "tools/cli/heat_factor_cache.hpp"

namespace locus::cli {
namespace {

struct CvtOptions {
  int32_t sites = 100;
  int32_t iterations = 10;
  double anisotropy = 0.0;
  std::string solver = "local";
  std::string t_text;
  bool no_refine = false;
  bool track = false;
  bool no_split = false;
  std::string centroid_t;   // --centroid-t T (the --t grammar)
  std::string t_centroid;   // --t-centroid C: deprecated, C h^2
  double fit_sigma = LloydOptions{}.fit_sigma;
  int fit_rings = LloydOptions{}.fit_rings;
  FactorCacheOptions fc;
  PreviewOptions preview;
  std::string labels_out, sites_out;
  int repair_rounds = RemeshOptions{}.max_repair_rounds;
  int refinements = RemeshOptions{}.max_refinements;
  bool no_hausdorff = false;
  int optimize_rounds = RemeshOptions{}.optimize_rounds;
  double stop_energy = 0.0;
};

// The centroids' own diffusion time (value 0: the cells' time). --t-centroid C,
// the spelling before the --t grammar, stays as an alias for a release.
TimeSpec centroid_time_spec(const CvtOptions& o) {
  if (!o.t_centroid.empty()) {
    if (!o.centroid_t.empty())
      fail(ErrorCode::BadUsage,
           "--centroid-t and --t-centroid name one time; give --centroid-t only (--t-centroid C is --centroid-t Ch2)");
    const double c = parse_h2_multiple(o.t_centroid, "--t-centroid", true);
    log("--t-centroid is deprecated and will be removed; use " +
        (c > 0 ? "--centroid-t " + o.t_centroid + "h2" : std::string("no option (0 is the cells' t)")));
    return TimeSpec{c, true};
  }
  return o.centroid_t.empty() ? TimeSpec{0.0, true} : parse_time_spec(o.centroid_t);
}

LloydOptions lloyd_options(const CommonOptions& opt, const CvtOptions& o, const TimeSpec& ts, const TimeSpec& tc) {
  LloydOptions lo;
  lo.sites = o.sites;
  lo.iterations = o.iterations;
  lo.stop_energy = o.stop_energy;
  lo.seed = opt.seed;
  lo.solver = o.solver == "full" ? LloydOptions::Solver::Full : LloydOptions::Solver::Local;
  lo.anisotropy = o.anisotropy;
  lo.refine = !o.no_refine;
  lo.track_quality = o.track;
  lo.split_faces = !o.no_split;
  (tc.times_h2 ? lo.t_centroid_factor : lo.t_centroid_abs) = tc.value;
  lo.fit_rings = o.fit_rings;
  lo.fit_sigma = o.fit_sigma;
  if (ts.times_h2) {
    lo.t_factor = ts.value;
  } else {
    lo.t_abs = ts.value;
  }
  return lo;
}

// The final sites as a point set (no faces): PLY keeps each site's face and
// barycentric weights (-1 and the vertex for sites on a vertex). `face` is a
// triangle of the mesh the command worked on; for a triangulated polygon file
// `polygon` names the file's face that triangle belongs to (-1 on a vertex).
void write_sites(const std::string& path, const Mesh& mesh, const LloydResult& r, const std::vector<int32_t>& face_of) {
  if (path.empty()) return;
  Mesh pts;
  WriteOptions wo;
  VertexProperty face{"face", VertexProperty::Type::Int, {}}, vert{"vertex", VertexProperty::Type::Int, {}};
  VertexProperty b[3] = {{"b0", VertexProperty::Type::Double, {}}, {"b1", VertexProperty::Type::Double, {}},
                         {"b2", VertexProperty::Type::Double, {}}};
  for (const SurfacePoint& p : r.sites) {
    const auto x = surface_point_position(mesh, p);
    pts.add_vertex(x[0], x[1], x[2]);
    face.values.push_back(p.face);
    vert.values.push_back(p.face < 0 ? p.vertex : -1);
    for (int k = 0; k < 3; ++k) b[k].values.push_back(p.bary[k]);
  }
  wo.vertex_properties = {face, vert, b[0], b[1], b[2]};
  if (!face_of.empty()) {
    VertexProperty polygon{"polygon", VertexProperty::Type::Int, {}};
    for (const SurfacePoint& p : r.sites) polygon.values.push_back(p.face < 0 ? -1 : face_of[p.face]);
    wo.vertex_properties.push_back(std::move(polygon));
  }
  write_mesh(path, pts, wo);
  log_written(path);
}

Json defects_json(const DualDefects& d) {
  return {{"split_cells", d.split_cells},
          {"non_disk_cells", d.non_disk_cells},
          {"split_interfaces", d.split_interfaces},
          {"loop_interfaces", d.loop_interfaces},
          {"boundary_interfaces", d.boundary_interfaces},
          {"repeated_corners", d.repeated_corners},
          {"split_boundary_runs", d.split_boundary_runs},
          {"short_boundary_loops", d.short_boundary_loops}};
}

// The `remesh` object (keys in the README's order) and the repair's counts.
Json remesh_json(const RemeshStats& st, const RemeshResult& rr) {
  Json j{{"vertices", st.vertices},
         {"faces", st.faces},
         {"manifold", st.manifold && rr.complete},
         {"genus", st.genus},
         {"components", st.components},
         {"boundary_loops", st.boundary_loops},
         {"mean_min_angle_deg", st.mean_min_angle_deg},
         {"min_angle_deg", st.min_angle_deg},
         {"pct_below_30_deg", st.pct_below_30_deg},
         {"hausdorff_rel", st.hausdorff_rel},
         {"added_sites", rr.added_sites}};
  j["dual_mean_min_angle_deg"] = rr.dual_mean_min_angle_deg;  // before the optimization
  j["dual_min_angle_deg"] = rr.dual_min_angle_deg;
  j["flips"] = rr.optimize.flips;
  j["smoothing_moves"] = rr.optimize.moves;
  j["boundary_moves"] = rr.optimize.boundary_moves;  // along the input's boundary curves
  j["repair_rounds"] = rr.repair_rounds;
  j["refinements"] = rr.refinements;
  j["lloyd_iterations"] = rr.lloyd_iterations;
  j["defects_before_repair"] = defects_json(rr.first_defects);
  j["defects_left"] = defects_json(rr.defects);
  return j;
}

// --preview: the remesh with its edges drawn dark (its vertices are the
// sites), or, without a manifold remesh, the input coloured by cell with the
// sites marked.
void write_cvt_preview(const Mesh& mesh, const RemeshResult& rr, const PreviewOptions& preview) {
  if (preview.path.empty()) return;
  const LloydResult& r = rr.lloyd;
  if (rr.complete) {
    const std::vector<double> one(rr.remesh.num_vertices(), 0.0);
    write_preview(rr.remesh, one, PreviewKind::Labels, preview,
                  {"cvt remesh: " + std::to_string(rr.remesh.num_vertices()) + " vertices (the sites), " +
                       std::to_string(rr.remesh.num_faces()) + " triangles",
                   {}, "", true});
    return;
  }
  PreviewContent pc{"cvt cells of " + std::to_string(r.sites.size()) + " sites (no remesh)", {}, "sites"};
  for (const SurfacePoint& p : r.sites) pc.markers.push_back(surface_point_position(mesh, p));
  write_preview(mesh, std::vector<double>(r.label.begin(), r.label.end()), PreviewKind::Labels, preview, pc);
}

Json lloyd_json(const CommonOptions& opt, const CvtOptions& o, const Mesh& mesh, const LloydResult& r,
                const CvtQuality& q) {
  Json j;
  j["n"] = mesh.num_vertices();
  j["sites"] = o.sites;
  j["iterations"] = o.iterations;
  j["stop_energy"] = o.stop_energy;
  j["seed"] = opt.seed;
  j["solver"] = o.solver;
  j["anisotropy"] = o.anisotropy;
  j["refine"] = !o.no_refine;
  j["h"] = r.h;
  j["t"] = r.t;
  j["t_centroid"] = r.t_centroid;
  j["init_s"] = r.init_s;
  j["factor_s"] = r.factor_s;  // includes the prepared operator's phases (0 when loaded)
  j["factor_mb"] = static_cast<double>(r.factor_bytes) / 1e6;
  j["iter_s"] = r.iter_s.empty() ? 0.0 : median(r.iter_s);
  j["final_labels_s"] = r.final_labels_s;
  j["phase_s"] = {{"labels", r.labels_s}, {"partition", r.partition_s}, {"neighbourhoods", r.neighborhood_s},
                  {"centroids", r.centroids_s}};
  j["mean_kept_fraction"] = r.mean_kept_fraction;
  j["dual_triangles"] = q.dual_triangles;
  j["min_angle_deg"] = q.min_angle_deg;
  j["mean_angle_deg"] = q.mean_angle_deg;
  {  // where the smallest angle is: its dual triangle's sites (ids, positions, cell areas)
    Json worst = Json::array();
    for (int32_t s : q.min_angle_sites)
      if (s >= 0) {
        const auto p = surface_point_position(mesh, r.sites[s]);
        // Sites added by the remesh's repair rounds have no split-cell area (the
        // incremental repair relabels vertices only): null.
        const Json area = static_cast<size_t>(s) < r.cell_area.size() ? Json(r.cell_area[s]) : Json(nullptr);
        worst.push_back({{"site", s}, {"xyz", {p[0], p[1], p[2]}}, {"cell_area", area}});
      }
    j["min_angle_sites"] = worst;
  }
  j["angle_histogram_5deg"] = std::vector<int64_t>(q.angle_histogram.begin(), q.angle_histogram.end());
  double cv = 0, var = 0;
  cell_area_spread(r.cell_area, cv, var);
  j["area_cv"] = cv;  // cells with triangles split along the bisectors
  j["area_variance"] = var;
  j["area_cv_vertex"] = q.area_cv;  // cells as unions of vertex stars (lumped mass)
  j["area_variance_vertex"] = q.area_variance;
  j["fallback_faces"] = r.fallback_faces;
  j["empty_cells"] = q.empty_cells;
  j["unreached_vertices"] = r.unreached;
  j["iter_s_all"] = r.iter_s;
  j["energy"] = r.energy;
  j["moved_h"] = r.moved;
  j["centroid_bias_h"] = r.centroid_bias;
  j["centroid_bias_median_h"] = r.centroid_bias_median;
  if (o.track) {
    j["mean_angle_all"] = r.mean_angle;
    j["min_angle_all"] = r.min_angle;
  }
  return j;
}

// Progress on stderr: a line when the phase changes, else at most one a second
// (the Lloyd loop reports every cell solve); nothing with --json.
std::function<void(double, std::string_view)> throttled_progress(bool json) {
  struct Throttle {
    std::mutex m;
    std::string phase;
    Stopwatch since;
  };
  auto throttle = std::make_shared<Throttle>();
  return [json, throttle](double f, std::string_view phase) {
    if (json) return;
    std::lock_guard<std::mutex> lock(throttle->m);
    if (phase == throttle->phase && throttle->since.seconds() < 1.0) return;
    throttle->phase = std::string(phase);
    throttle->since.restart();
    log(std::string(phase) + " " + std::to_string(static_cast<int>(100 * f + 0.5)) + "%");
  };
}

int run_cvt(const CommonOptions& opt, const CvtOptions& o, const RunContext& ctx) {
  if (o.solver != "local" && o.solver != "full")
    fail(ErrorCode::BadUsage, "--solver must be 'local' or 'full', got '" + o.solver + "'");
  // Default 4h^2, not the thesis's h^2: better cells and centroids on irregular meshes
  // (measurements in docs/cvt.md).
  const TimeSpec ts = o.t_text.empty() ? TimeSpec{kLloydTFactor, true} : parse_time_spec(o.t_text);
  const TimeSpec tc = centroid_time_spec(o);
  validate_factor_cache_options(o.fc);
  check_preview_options(o.preview);
  if (o.anisotropy > 0 && (!o.fc.save.empty() || !o.fc.load.empty()))
    fail(ErrorCode::BadUsage, "--save/--load cache the isotropic operator; not with --anisotropy");
  const Stopwatch total;
  Input in = load_input(opt, ctx);
  const Mesh& mesh = in.mesh;
  const double load_s = total.seconds();
  // Refusals that depend on the file are bad input (exit 3), like the file's own defects.
  if (o.sites > mesh.num_vertices())
    fail(ErrorCode::BadInput, opt.mesh_path + ": --sites " + std::to_string(o.sites) + " exceeds the " +
                                  std::to_string(mesh.num_vertices()) + " vertices of the mesh");
  const MeshDerived derived = derive_mesh(mesh);
  if (o.sites < derived.components)
    fail(ErrorCode::BadInput, opt.mesh_path + ": --sites " + std::to_string(o.sites) + " for " +
                                  std::to_string(derived.components) +
                                  " connected components; every component needs at least one site");
  RemeshOptions ro;
  ro.lloyd = lloyd_options(opt, o, ts, tc);
  ro.max_repair_rounds = o.repair_rounds;
  ro.max_refinements = o.refinements;
  ro.optimize_rounds = o.optimize_rounds;
  RunContext run = ctx;
  run.progress = throttled_progress(opt.json);
  // The cells' operator through the factor cache (isotropic); cvt_lloyd factors the lifted one itself.
  Stopwatch phase;
  Factors cache;
  HeatDiffusion prepared;
  if (o.anisotropy == 0) {
    prepared = heat_diffusion_cached(o.fc, in, ts, ctx, cache);
    ro.lloyd.prepared = &prepared;
  }
  const double factor_s = phase.seconds();
  const RemeshResult rr = cvt_remesh(mesh, derived, ro, run);
  const LloydResult& r = rr.lloyd;
  if (!opt.output.empty() && !rr.complete)
    fail(ErrorCode::Numerical, "cvt: the cells still break the closed-ball property after " +
                                   std::to_string(rr.repair_rounds) + " repair rounds (" +
                                   defects_json(rr.defects).dump() + "); no manifold remesh to write to " +
                                   opt.output + " (try more --sites, --repair-rounds or --refinements)");
  phase.restart();
  write_output_mesh(opt, rr.remesh);
  const double write_s = phase.seconds();
  const double total_s = total.seconds();
  phase.restart();
  const RemeshStats st = rr.complete ? remesh_stats(mesh, rr.remesh, !o.no_hausdorff) : RemeshStats{};
  const RemeshStats in_st = mesh_topology_stats(mesh);
  const double stats_s = phase.seconds();
  if (!o.labels_out.empty()) {
    WriteOptions wo = carried_attributes(in);
    add_result(wo, {"label", VertexProperty::Type::Int, std::vector<double>(r.label.begin(), r.label.end())});
    write_mesh(o.labels_out, output_faces(in), wo);
    log_written(o.labels_out);
  }
  write_sites(o.sites_out, mesh, r, in.face_of);
  write_cvt_preview(mesh, rr, o.preview);
  const CvtQuality q = cvt_quality(mesh, r.label, r.sites);
  Json j{{"command", "cvt"}, {"input", input_json(opt, in)}};
  j.update(lloyd_json(opt, o, mesh, r, q));
  j["factor_cache"] = factor_cache_json(o.fc, cache);
  j["remesh"] = remesh_json(st, rr);
  j["remesh"]["input"] = {{"genus", in_st.genus}, {"components", in_st.components},
                          {"boundary_loops", in_st.boundary_loops}};
  j["timings"] = {{"load_s", load_s},     {"subdivide_s", in.subdivide_s}, {"factor_s", factor_s + rr.factor_s},
                  {"lloyd_s", rr.lloyd_s}, {"repair_s", rr.repair_s},      {"dual_s", rr.dual_s},
                  {"optimize_s", rr.optimize_s}, {"write_s", write_s},   {"total_s", total_s},
                  {"stats_s", stats_s}};
  // The same numbers under the names of earlier releases (deprecated; `timings` is the contract).
  j["timings_s"] = {{"load", load_s},          {"factor", factor_s + rr.factor_s}, {"lloyd", rr.lloyd_s},
                    {"repair", rr.repair_s},   {"dual", rr.dual_s},                {"optimize", rr.optimize_s},
                    {"write", write_s},
                    {"total", total_s},        {"stats", stats_s}};
  emit(opt, j, [&](std::ostream& os) {
    os << opt.mesh_path << ": CVT of " << o.sites << " sites on " << mesh.num_vertices() << " vertices, "
       << rr.lloyd_iterations << " Lloyd iterations (" << o.solver << " solves"
       << (o.anisotropy > 0 ? ", anisotropic" : "") << ")\n";
    if (rr.complete) {
      os << "  remesh: " << st.vertices << " vertices, " << st.faces << " triangles ("
         << rr.added_sites << " sites added), genus " << st.genus << ", " << st.components << " component(s), "
         << st.boundary_loops << " boundary loop(s)" << (st.manifold ? ", manifold" : ", NOT manifold") << "\n"
         << "  smallest angle per triangle: mean " << st.mean_min_angle_deg << " deg, min " << st.min_angle_deg
         << " deg, " << st.pct_below_30_deg << "% below 30; Hausdorff " << st.hausdorff_rel
         << " of the bounding-box diagonal\n";
    } else {
      os << "  no manifold remesh: defects left " << defects_json(rr.defects).dump() << "\n";
    }
    os << "  total " << total_s << " s (load to written file)\n";
    if (!opt.output.empty()) os << "  remesh written to " << opt.output << "\n";
    if (!o.preview.path.empty()) os << "  preview written to " << o.preview.path << "\n";
  });
  return 0;
}

}  // namespace

// Defined in cmd_nncoords.cpp and cmd_skinweights.cpp; registered with cvt so that
// main.cpp's registration list does not change.
void register_nncoords_command(CommandTable& table);
void register_skinweights_command(CommandTable& table);

void register_cvt_command(CommandTable& table) {
  register_nncoords_command(table);
  register_skinweights_command(table);
  auto o = std::make_shared<CvtOptions>();
  CLI::App* app = table.add("cvt", "Centroidal Voronoi tessellation (Lloyd with heat cells and centroids)",
                            [o](const CommonOptions& opt, const RunContext& ctx) { return run_cvt(opt, *o, ctx); });
  app->add_option("--sites", o->sites, "Number of sites (random initial positions, --seed)")
      ->check(CLI::Range(1, 100000000));
  app->add_option("--iters", o->iterations, "Lloyd iterations (default 10)")->check(CLI::Range(0, 1000000));
  app->add_option("--stop-energy", o->stop_energy,
                  "Stop Lloyd once an iteration lowers the CVT energy by less than this fraction (default 0: all --iters)")
      ->check(CLI::Range(0.0, 1.0));
  app->add_option("--anisotropy", o->anisotropy, "lambda of the R^6 lift (p, lambda n); 0 = isotropic (thesis: 0.05)")
      ->check(CLI::Range(0.0, 1e6));
  app->add_option("--solver", o->solver, "local (approximate selective solves, default) or full");
  app->add_option("--t", o->t_text, "Diffusion time: absolute or a multiple of h^2 (h2, 4h2); default 4h2 (thesis: h2)")->check(non_empty());
  add_factor_cache_options(app, o->fc);
  add_preview_option(app, o->preview);
  app->add_flag("--no-refine", o->no_refine, "Centroids at the hottest vertex (no quadratic fit)");
  app->add_option("--centroid-t", o->centroid_t,
                  "Centroid diffusion time, as --t: absolute or a multiple of h^2 (2h2); default: the cells' t")
      ->check(non_empty());
  app->add_option("--t-centroid", o->t_centroid, "Deprecated spelling of --centroid-t: --t-centroid C is --centroid-t Ch2")
      ->check(non_empty());
  app->add_option("--fit-rings", o->fit_rings, "Vertex rings of the centroid's quadratic fit (default 2; the thesis fits 1)")
      ->check(CLI::Range(1, 4));
  app->add_option("--fit-sigma", o->fit_sigma,
                  "Weighted refit of the centroid's maximizer, Gaussian width in one-ring distances (default 1; 0 = none)")
      ->check(CLI::Range(0.0, 100.0));
  app->add_flag("--no-split", o->no_split, "Cell sources from vertex labels only (no split triangles)");
  // Checked at parse time like -o: a bad target is exit 2 before any work.
  app->add_option("--labels", o->labels_out, "Write the input mesh with a per-vertex `label` property (the cell) (PLY)")
      ->check(output_file({"ply", "obj", "off"}));
  app->add_option("--sites-out", o->sites_out, "Write the final sites as points (PLY keeps face and barycentrics)")
      ->check(output_file({"ply", "obj", "off"}));
  app->add_option("--repair-rounds", o->repair_rounds,
                  "Rounds of added sites that make the remesh a manifold (default 12)")
      ->check(CLI::Range(0, 1000));
  app->add_option("--refinements", o->refinements,
                  "Midpoint subdivisions of the input the repair may use where its vertices are too coarse for "
                  "the cells (default 3; 0 = none)")
      ->check(CLI::Range(0, 4));
  app->add_option("--optimize", o->optimize_rounds,
                  "Rounds of edge flips and tangential smoothing of the remesh on the input (default 4; 0 = the dual as is)")
      ->check(CLI::Range(0, 100));
  app->add_flag("--no-hausdorff", o->no_hausdorff, "Skip the Hausdorff distance of the remesh (JSON -1)");
  app->add_flag("--track-quality", o->track, "JSON mean_angle_all/min_angle_all: dual angles of every iteration");
}

}  // namespace locus::cli
