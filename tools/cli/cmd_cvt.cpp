// `locus cvt MESH`: centroidal Voronoi tessellation by Lloyd's method with heat
// cells and centroids (thesis §3.7.1), localized (approximate selective
// solves, default) or with full solves (--solver full, for comparison),
// isotropic or anisotropic (--anisotropy lambda), computed by
// locus::Session::cvt (engine/include/locus/engine/cvt_request.hpp), which
// owns the checks. -o writes the remesh: the restricted-Delaunay dual of the
// final cells, repaired into a manifold with the input's topology; --labels
// writes the input with a per-vertex `label` property (the cell), --sites-out
// the sites; --json reports the timings, the `remesh` object and the quality
// of the cells.
#include <functional>
#include <memory>
#include <mutex>
#include <ostream>
#include <string>
#include <vector>

#include "locus/engine/cvt_request.hpp"
#include "locus/error.hpp"
#include "locus/mesh_io.hpp"
#include "locus/session.hpp"
#include "tools/cli/cli_common.hpp"
#include "tools/cli/written_files.hpp"

namespace locus::cli {
namespace {

struct CvtOptions {
  CvtRequest request;
  PreviewOptions preview;
};

Json defects_json(const CvtDefects& d) {
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
Json remesh_json(const CvtRequest& q, const CvtReport& r) {
  const CvtMeshStats& st = r.remesh_stats;
  Json j{{"vertices", st.vertices},
         {"faces", st.faces},
         {"manifold", st.manifold && r.complete},
         {"genus", st.genus},
         {"components", st.components},
         {"boundary_loops", st.boundary_loops},
         {"mean_min_angle_deg", st.mean_min_angle_deg},
         {"min_angle_deg", st.min_angle_deg},
         {"pct_below_30_deg", st.pct_below_30_deg},
         {"hausdorff_rel", st.hausdorff_rel},
         {"added_sites", r.added_sites}};
  j["dual_mean_min_angle_deg"] = r.dual_mean_min_angle_deg;  // before the optimization
  j["dual_min_angle_deg"] = r.dual_min_angle_deg;
  j["flips"] = r.flips;
  j["smoothing_moves"] = r.smoothing_moves;
  j["boundary_moves"] = r.boundary_moves;  // along the input's boundary curves (and feature curves)
  if (q.features > 0)  // the input's edges above the dihedral angle, their curves and corners, the sites on them
    j["features"] = {{"angle_deg", q.features},
                     {"edges", r.feature_edges},
                     {"curves", r.feature_curves},
                     {"corners", r.feature_corners},
                     {"sites", r.feature_sites}};
  j["repair_rounds"] = r.repair_rounds;
  j["refinements"] = r.refinements;
  j["lloyd_iterations"] = r.lloyd_iterations;
  j["requested"] = r.requested;  // sites asked for, against the remesh vertices delivered
  j["delivered"] = r.delivered;
  j["repair_sites"] = r.repair_sites;
  j["removed_sites"] = r.removed_sites;
  j["density_passes"] = r.density_passes;
  j["geodesic_rounds"] = r.geodesic_rounds;
  j["rebalance_rounds"] = r.rebalance_rounds;
  j["single_triangles"] = r.single_triangles;
  j["defects_before_repair"] = defects_json(r.defects_before_repair);
  j["defects_left"] = defects_json(r.defects_left);
  const CvtMeshStats& in = r.input_stats;
  j["input"] = {{"genus", in.genus}, {"components", in.components}, {"boundary_loops", in.boundary_loops}};
  if (r.sheets.cut) {  // a mesh that is not a manifold: remeshed as its manifold sheets (the input's topology is theirs)
    const CvtSheets& c = r.sheets;
    j["sheets"] = {{"split_vertices", c.split_vertices}, {"cut_edges", c.cut_edges},
                   {"flipped_faces", c.flipped_faces},   {"dropped_faces", c.dropped_faces},
                   {"split_faces", c.split_faces},       {"unreferenced_vertices", c.unreferenced_vertices}};
  }
  return j;
}

std::array<double, 3> site_position(const CvtReport& r, size_t s) {
  return {r.site_xyz[3 * s], r.site_xyz[3 * s + 1], r.site_xyz[3 * s + 2]};
}

// --preview: the remesh with its edges drawn dark (its vertices are the
// sites), or, without a manifold remesh, the input coloured by cell with the
// sites marked.
void write_cvt_preview(const Mesh& mesh, const CvtReport& r, const PreviewOptions& preview) {
  if (preview.path.empty()) return;
  if (r.complete) {
    const std::vector<double> one(r.remesh.num_vertices(), 0.0);
    write_preview(r.remesh, one, PreviewKind::Labels, preview,
                  {"cvt remesh: " + std::to_string(r.remesh.num_vertices()) + " vertices (the sites), " +
                       std::to_string(r.remesh.num_faces()) + " triangles",
                   {}, "", true});
    return;
  }
  const size_t ns = r.site_face.size();
  PreviewContent pc{"cvt cells of " + std::to_string(ns) + " sites (no remesh)", {}, "sites"};
  for (size_t s = 0; s < ns; ++s) pc.markers.push_back(site_position(r, s));
  write_preview(mesh, std::vector<double>(r.label.begin(), r.label.end()), PreviewKind::Labels, preview, pc);
}

Json lloyd_json(const CommonOptions& opt, const CvtRequest& o, const CvtReport& r) {
  Json j;
  j["n"] = r.n;
  j["sites"] = o.sites;
  j["iterations"] = o.iters;
  j["stop_energy"] = o.stop_energy;
  j["seed"] = opt.seed;
  j["solver"] = o.solver;
  j["anisotropy"] = o.anisotropy;
  j["refine"] = !o.no_refine;
  j["h"] = r.h;
  j["t"] = r.t;
  j["t_centroid"] = r.t_centroid;
  j["init_s"] = r.init_s;
  j["factor_s"] = r.lloyd_factor_s;  // includes the prepared operator's phases (0 when loaded)
  j["factor_mb"] = static_cast<double>(r.factor_bytes) / 1e6;
  j["iter_s"] = r.iter_s.empty() ? 0.0 : median(r.iter_s);
  j["final_labels_s"] = r.final_labels_s;
  j["phase_s"] = {{"labels", r.labels_s}, {"partition", r.partition_s}, {"neighbourhoods", r.neighbourhoods_s},
                  {"centroids", r.centroids_s}};
  j["mean_kept_fraction"] = r.mean_kept_fraction;
  j["dual_triangles"] = r.dual_triangles;
  j["min_angle_deg"] = r.cells_min_angle_deg;
  j["mean_angle_deg"] = r.cells_mean_angle_deg;
  {  // where the smallest angle is: its dual triangle's sites (ids, positions, cell areas)
    Json worst = Json::array();
    for (int32_t s : r.min_angle_sites)
      if (s >= 0) {
        const auto p = site_position(r, static_cast<size_t>(s));
        // Sites added by the remesh's repair rounds have no split-cell area (the
        // incremental repair relabels vertices only): null.
        const Json area = static_cast<size_t>(s) < r.cell_area.size() ? Json(r.cell_area[s]) : Json(nullptr);
        worst.push_back({{"site", s}, {"xyz", {p[0], p[1], p[2]}}, {"cell_area", area}});
      }
    j["min_angle_sites"] = worst;
  }
  j["angle_histogram_5deg"] = std::vector<int64_t>(r.angle_histogram.begin(), r.angle_histogram.end());
  j["area_cv"] = r.area_cv;  // cells with triangles split along the bisectors
  j["area_variance"] = r.area_variance;
  j["area_cv_vertex"] = r.area_cv_vertex;  // cells as unions of vertex stars (lumped mass)
  j["area_variance_vertex"] = r.area_variance_vertex;
  j["fallback_faces"] = r.fallback_faces;
  j["empty_cells"] = r.empty_cells;
  j["unreached_vertices"] = r.unreached;
  j["iter_s_all"] = r.iter_s;
  j["energy"] = r.energy;
  j["moved_h"] = r.moved;
  j["centroid_bias_h"] = r.centroid_bias;
  j["centroid_bias_median_h"] = r.centroid_bias_median;
  if (o.track_quality) {
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

Json cvt_json(const CommonOptions& opt, const CvtRequest& q, const Input& in, const CvtReport& r, double load_s,
              double write_s, double total_s) {
  Json j{{"command", "cvt"}, {"input", input_json(opt, in)}};
  j.update(lloyd_json(opt, q, r));
  j["factor_cache"] = factor_cache_json(r.factor_cache);
  j["remesh"] = remesh_json(q, r);
  const double factor_s = r.prepare_s + r.remesh_factor_s;
  j["timings"] = {{"load_s", load_s},       {"subdivide_s", in.subdivide_s}, {"factor_s", factor_s},
                  {"lloyd_s", r.lloyd_s},   {"repair_s", r.repair_s},        {"dual_s", r.dual_s},
                  {"optimize_s", r.optimize_s}, {"write_s", write_s},        {"total_s", total_s},
                  {"stats_s", r.stats_s}};
  // The same numbers under the names of earlier releases (deprecated; `timings` is the contract).
  j["timings_s"] = {{"load", load_s},         {"factor", factor_s}, {"lloyd", r.lloyd_s},
                    {"repair", r.repair_s},   {"dual", r.dual_s},   {"optimize", r.optimize_s},
                    {"write", write_s},       {"total", total_s},   {"stats", r.stats_s}};
  return j;
}

void print_cvt(std::ostream& os, const CommonOptions& opt, const CvtOptions& o, const CvtReport& r, double total_s) {
  const CvtRequest& q = o.request;
  const CvtMeshStats& st = r.remesh_stats;
  os << opt.mesh_path << ": CVT of " << q.sites << " sites on " << r.n << " vertices, " << r.lloyd_iterations
     << " Lloyd iterations (" << q.solver << " solves" << (q.anisotropy > 0 ? ", anisotropic" : "") << ")\n";
  if (r.complete) {
    os << "  remesh: " << st.vertices << " vertices, " << st.faces << " triangles (" << r.added_sites
       << " sites added), genus " << st.genus << ", " << st.components << " component(s), " << st.boundary_loops
       << " boundary loop(s)" << (st.manifold ? ", manifold" : ", NOT manifold") << "\n"
       << "  smallest angle per triangle: mean " << st.mean_min_angle_deg << " deg, min " << st.min_angle_deg
       << " deg, " << st.pct_below_30_deg << "% below 30; Hausdorff " << st.hausdorff_rel
       << " of the bounding-box diagonal\n";
  } else {
    os << "  no manifold remesh: defects left " << defects_json(r.defects_left).dump() << "\n";
  }
  os << "  total " << total_s << " s (load to written file)\n";
  if (!opt.output.empty()) os << "  remesh written to " << opt.output << "\n";
  if (!o.preview.path.empty()) os << "  preview written to " << o.preview.path << "\n";
}

int run_cvt(const CommonOptions& opt, CvtOptions& o, const RunContext& ctx) {
  CvtRequest& q = o.request;
  q.seed = opt.seed;
  check_request(q);  // bad usage before reading the file
  check_preview_options(o.preview);
  const Stopwatch total;
  Input in = load_input_for_session(opt, ctx);
  const double load_s = total.seconds();
  // A triangle mesh is moved into the Session (not copied: at 416k vertices a copy
  // is ~30 MB held through Lloyd) and copied back once the remesh is done.
  const bool lend = in.mesh.is_triangle_mesh();
  SessionOptions so = session_options(in);
  so.exclusive = true;  // one command on it: its edge incidence is freed while Lloyd runs
  const Session session{lend ? std::move(in.mesh) : Mesh(in.mesh), so};
  take_session_operator(in, session, ctx);
  // The files on the input's vertices are written below, with the file's faces and attributes.
  CvtRequest engine = q;
  engine.labels.clear();
  engine.sites_out.clear();
  RunContext run = ctx;
  run.progress = throttled_progress(opt.json);
  const CvtReport r = session.cvt(engine, run);
  if (lend) in.mesh = session.mesh();
  if (!opt.output.empty() && !r.complete)
    fail(ErrorCode::Numerical, "cvt: the cells still break the closed-ball property after " +
                                   std::to_string(r.repair_rounds) + " repair rounds (" +
                                   defects_json(r.defects_left).dump() + "); no manifold remesh to write to " +
                                   opt.output + " (try more --sites, --repair-rounds or --refinements)");
  Stopwatch phase;
  write_output_mesh(opt, r.remesh);
  const double write_s = phase.seconds();
  const double total_s = total.seconds();
  WriteOptions carried = carried_attributes(in);
  write_cvt_files(q, r, output_faces(in), std::move(carried), in.face_of);
  if (!q.labels.empty()) log_written(q.labels);
  if (!q.sites_out.empty()) log_written(q.sites_out);
  write_cvt_preview(in.mesh, r, o.preview);
  emit(opt, cvt_json(opt, q, in, r, load_s, write_s, total_s),
       [&](std::ostream& os) { print_cvt(os, opt, o, r, total_s); });
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
  CvtRequest& q = o->request;
  CLI::App* app = table.add("cvt", "Centroidal Voronoi tessellation (Lloyd with heat cells and centroids)",
                            [o](const CommonOptions& opt, const RunContext& ctx) { return run_cvt(opt, *o, ctx); });
  app->add_option("--sites", q.sites, "Number of sites (random initial positions, --seed)")
      ->check(CLI::Range(1, 100000000));
  app->add_option("--iters", q.iters, "Lloyd iterations (default 10)")->check(CLI::Range(0, 1000000));
  app->add_option("--stop-energy", q.stop_energy,
                  "Stop Lloyd once an iteration lowers the CVT energy by less than this fraction (default 0: all --iters)")
      ->check(CLI::Range(0.0, 1.0));
  app->add_option("--anisotropy", q.anisotropy, "lambda of the R^6 lift (p, lambda n); 0 = isotropic (thesis: 0.05)")
      ->check(CLI::Range(0.0, 1e6));
  app->add_option("--solver", q.solver, "local (approximate selective solves, default) or full");
  app->add_option("--t", q.t, "Diffusion time: absolute or a multiple of h^2 (h2, 4h2); default 4h2 (thesis: h2)")->check(non_empty());
  add_factor_cache_options(app, q.save, q.load);
  add_preview_option(app, o->preview);
  app->add_flag("--no-refine", q.no_refine, "Centroids at the hottest vertex (no quadratic fit)");
  app->add_option("--centroid-t", q.centroid_t,
                  "Centroid diffusion time, as --t: absolute or a multiple of h^2 (2h2); default: the cells' t")
      ->check(non_empty());
  app->add_option("--t-centroid", q.t_centroid, "Deprecated spelling of --centroid-t: --t-centroid C is --centroid-t Ch2")
      ->check(non_empty());
  app->add_option("--fit-rings", q.fit_rings, "Vertex rings of the centroid's quadratic fit (default 2; the thesis fits 1)")
      ->check(CLI::Range(1, 4));
  app->add_option("--fit-sigma", q.fit_sigma,
                  "Weighted refit of the centroid's maximizer, Gaussian width in one-ring distances (default 1; 0 = none)")
      ->check(CLI::Range(0.0, 100.0));
  app->add_flag("--no-split", q.no_split, "Cell sources from vertex labels only (no split triangles)");
  // Checked at parse time like -o: a bad target is exit 2 before any work.
  app->add_option("--labels", q.labels, "Write the input mesh with a per-vertex `label` property (the cell) (PLY)")
      ->check(output_file({"ply", "obj", "off"}));
  app->add_option("--sites-out", q.sites_out, "Write the final sites as points (PLY keeps face and barycentrics)")
      ->check(output_file({"ply", "obj", "off"}));
  app->add_option("--repair-rounds", q.repair_rounds,
                  "Rounds of added sites that make the remesh a manifold (default 12)")
      ->check(CLI::Range(0, 1000));
  app->add_option("--refinements", q.refinements,
                  "Midpoint subdivisions of the input the repair may use where its vertices are too coarse for "
                  "the cells (default 3; 0 = none)")
      ->check(CLI::Range(0, 4));
  app->add_option("--optimize", q.optimize,
                  "Rounds of edge flips and tangential smoothing of the remesh on the input (default 6; 0 = the dual as is)")
      ->check(CLI::Range(0, 100));
  // Checked by the engine (check_request): NaN, negative or >= 180 is exit 2.
  app->add_option("--features", q.features,
                  "Keep sharp features: input edges whose dihedral angle (between the normals of their two faces) "
                  "exceeds DEG degrees become remesh edges, their corners remesh vertices (0 <= DEG < 180; default 0 = "
                  "none; e.g. 30 for CAD parts)");
  app->add_flag("--no-hausdorff", q.no_hausdorff, "Skip the Hausdorff distance of the remesh (JSON -1)");
  app->add_flag("--track-quality", q.track_quality, "JSON mean_angle_all/min_angle_all: dual angles of every iteration");
}

}  // namespace locus::cli
