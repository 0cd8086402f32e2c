// `cvt` as every front end runs it (engine/include/locus/engine/
// cvt_request.hpp): the checks of the request, the cells' operator M - tL
// factored or loaded by the command (command_heat_operator.hpp; the lifted
// operator of an anisotropic run is cvt_lloyd's own), Lloyd's method with
// heat cells and centroids (thesis §3.7.1, pipelines/.../voronoi/
// cvt_lloyd.hpp), the remesh (cvt_remesh.hpp) and the statistics the CLI
// reports (remesh_quality.hpp, cvt_quality.hpp). run_cvt is also the cached
// tier's (Session::cvt(sites, iterations, seed) with remesh), on the
// Session's kept operator.
#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <oneapi/tbb/parallel_invoke.h>

#include "command_clock.hpp"
#include "command_heat_operator.hpp"
#include "cvt_sheets.hpp"
#include "field_copy.hpp"
#include "face_corner_loan.hpp"
#include "incidence_loan.hpp"
#include "locus/core/release_free_memory.hpp"
#include "locus/engine/cvt_request.hpp"
#include "locus/error.hpp"
#include "locus/io/atomic_file_write.hpp"
#include "locus/io/file_extension.hpp"
#include "locus/kernels/heat/surface_point.hpp"
#include "locus/kernels/mesh/subdivision_budget.hpp"
#include "locus/pipelines/voronoi/cvt_quality.hpp"
#include "locus/pipelines/voronoi/cvt_remesh.hpp"
#include "locus/pipelines/voronoi/remesh_quality.hpp"
#include "session_state.hpp"

namespace locus {
namespace {

using namespace session_detail;

using command_clock::seconds;

void check_count(const char* option, int64_t v, int64_t lo, int64_t hi) {
  if (v < lo || v > hi)
    fail(ErrorCode::BadUsage, std::string(option) + " must be in " + std::to_string(lo) + ".." + std::to_string(hi) +
                                  " (got " + std::to_string(v) + ")");
}

void check_range(const char* option, double v, double lo, double hi) {
  if (!(v >= lo && v <= hi))
    fail(ErrorCode::BadUsage, std::string(option) + " must be in " + format_number(lo) + ".." + format_number(hi) +
                                  " (got " + format_number(v) + ")");
}

// An output file of the request: a mesh format, in a folder that exists.
void check_mesh_target(const char* option, const std::string& path) {
  if (path.empty()) return;
  const std::string ext = io::lower_extension(path);
  if (ext != "ply" && ext != "obj" && ext != "off")
    fail(ErrorCode::BadUsage, std::string(option) + " " + path + ": unsupported extension '" + ext +
                                  "' (expected .ply, .obj, .off)");
  io::check_output_path(path);
}

// The deprecated spelling's bare number C >= 0 (a multiple of h^2).
double h2_multiple(const std::string& text) {
  double c = -1;
  const char* first = text.data();
  const char* last = first + text.size();
  auto [ptr, ec] = std::from_chars(first, last, c);
  if (ec != std::errc() || ptr != last || !(c >= 0) || !std::isfinite(c))
    fail(ErrorCode::BadUsage, "--t-centroid must be a finite number >= 0 (got '" + text + "')");
  return c;
}

// The centroids' own diffusion time (value 0: the cells' time). t_centroid C,
// the spelling before the time grammar, stays as an alias for a release;
// `ctx` (when given) receives the deprecation note.
HeatTime centroid_time(const CvtRequest& req, const RunContext* ctx) {
  if (!req.t_centroid.empty()) {
    if (!req.centroid_t.empty())
      fail(ErrorCode::BadUsage,
           "--centroid-t and --t-centroid name one time; give --centroid-t only (--t-centroid C is --centroid-t Ch2)");
    const double c = h2_multiple(req.t_centroid);
    if (ctx)
      ctx->note("--t-centroid is deprecated and will be removed; use " +
                (c > 0 ? "--centroid-t " + req.t_centroid + "h2" : std::string("no option (0 is the cells' t)")));
    return HeatTime{c, true};
  }
  return req.centroid_t.empty() ? HeatTime{0.0, true} : parse_heat_time(req.centroid_t, "--centroid-t");
}

LloydOptions lloyd_options(const CvtRequest& req, const HeatTime& ts, const HeatTime& tc) {
  LloydOptions lo;
  lo.sites = req.sites;
  lo.iterations = req.iters;
  lo.stop_energy = req.stop_energy;
  lo.seed = req.seed;
  lo.solver = req.solver == "full" ? LloydOptions::Solver::Full : LloydOptions::Solver::Local;
  lo.anisotropy = req.anisotropy;
  lo.refine = !req.no_refine;
  lo.track_quality = req.track_quality;
  lo.split_faces = !req.no_split;
  (tc.times_h2 ? lo.t_centroid_factor : lo.t_centroid_abs) = tc.value;
  lo.fit_rings = req.fit_rings;
  lo.fit_sigma = req.fit_sigma;
  (ts.times_h2 ? lo.t_factor : lo.t_abs) = ts.value;
  return lo;
}

CvtDefects defects_of(const DualDefects& d) {
  return {d.split_cells,         d.non_disk_cells,   d.split_interfaces,    d.loop_interfaces,
          d.boundary_interfaces, d.repeated_corners, d.split_boundary_runs, d.short_boundary_loops};
}

CvtMeshStats stats_of(const RemeshStats& st) {
  CvtMeshStats s;
  s.vertices = st.vertices, s.faces = st.faces, s.manifold = st.manifold, s.genus = st.genus;
  s.components = st.components, s.boundary_loops = st.boundary_loops;
  s.mean_min_angle_deg = st.mean_min_angle_deg, s.min_angle_deg = st.min_angle_deg;
  s.pct_below_30_deg = st.pct_below_30_deg, s.hausdorff_rel = st.hausdorff_rel;
  return s;
}

// The last Lloyd run's cells, sites and figures.
void take_lloyd(const Mesh& mesh, LloydResult& lr, CvtReport& r) {
  r.label.assign(lr.label.begin(), lr.label.end());
  for (const SurfacePoint& p : lr.sites) {
    const std::array<double, 3> x = surface_point_position(mesh, p);
    r.site_xyz.insert(r.site_xyz.end(), x.begin(), x.end());
    r.site_face.push_back(p.face);
    r.site_vertex.push_back(p.face < 0 ? p.vertex : -1);
    r.site_bary.insert(r.site_bary.end(), p.bary.begin(), p.bary.end());
  }
  r.n = mesh.num_vertices();
  r.h = lr.h, r.t = lr.t, r.t_centroid = lr.t_centroid;
  r.factor_bytes = lr.factor_bytes;
  r.mean_kept_fraction = lr.mean_kept_fraction;
  r.fallback_faces = lr.fallback_faces, r.unreached = lr.unreached, r.lloyd_empty_cells = lr.empty_cells;
  cell_area_spread(lr.cell_area, r.area_cv, r.area_variance);
  r.cell_area = std::move(lr.cell_area);
  r.energy = std::move(lr.energy), r.moved = std::move(lr.moved);
  r.centroid_bias = std::move(lr.centroid_bias), r.centroid_bias_median = std::move(lr.centroid_bias_median);
  r.mean_angle = std::move(lr.mean_angle), r.min_angle = std::move(lr.min_angle);
  r.init_s = lr.init_s, r.lloyd_factor_s = lr.factor_s, r.final_labels_s = lr.final_labels_s;
  r.iter_s = std::move(lr.iter_s);
  r.labels_s = lr.labels_s, r.partition_s = lr.partition_s, r.neighbourhoods_s = lr.neighborhood_s;
  r.centroids_s = lr.centroids_s;
}

void take_quality(const CvtQuality& q, CvtReport& r) {
  r.dual_triangles = q.dual_triangles;
  r.cells_min_angle_deg = q.min_angle_deg, r.cells_mean_angle_deg = q.mean_angle_deg;
  r.min_angle_sites = q.min_angle_sites;
  r.angle_histogram = q.angle_histogram;
  r.area_cv_vertex = q.area_cv, r.area_variance_vertex = q.area_variance;
  r.empty_cells = q.empty_cells;
}

// The Session's derived data, lent to the command (SessionOptions::exclusive:
// nobody else reads it while the command runs). check_and_derive creates it
// non-const; the State holds it as const for every concurrent reader.
MeshDerived* exclusive_derived(const session_detail::State& s) { return const_cast<MeshDerived*>(s.derived.get()); }

}  // namespace

CvtReport run_cvt(const Mesh& mesh, const MeshDerived& derived, const CvtRequest& req, const HeatTime& ts,
                  const HeatTime& tc, const HeatDiffusion* prepared, const RunContext& ctx,
                  std::function<void()> operator_done, std::function<void()> lloyd_done,
                  std::function<void()> corners_needed) {
  RemeshOptions ro;
  ro.lloyd = lloyd_options(req, ts, tc);
  ro.lloyd.prepared = prepared;
  ro.operator_done = std::move(operator_done);
  ro.lloyd_done = std::move(lloyd_done);
  ro.corners_needed = std::move(corners_needed);
  ro.max_repair_rounds = req.repair_rounds;
  ro.max_refinements = req.refinements;
  ro.optimize_rounds = req.optimize;
  ro.feature_angle_deg = req.features;
  ro.hausdorff = !req.no_hausdorff;
  RemeshResult rr = cvt_remesh(mesh, derived, ro, ctx);
  // Crease networks longer than the density samples (cheese at 1,000 sites:
  // 1,652 feature sites) leave the optimization almost nothing to move.
  if (rr.feature_sites > 0 && 2 * static_cast<int64_t>(rr.feature_sites) > rr.requested)
    ctx.note(mesh_name(mesh) + ": --features " + format_number(req.features) + ": the feature curves need " +
             std::to_string(rr.feature_sites) + " sites at the spacing of --sites " + std::to_string(rr.requested) +
             ", more than half as many; the triangles between the curves have little room to improve (ask for about " +
             std::to_string(4 * static_cast<int64_t>(rr.feature_sites)) + " sites, or a larger feature angle)");
  CvtReport r;
  auto t0 = std::chrono::steady_clock::now();
  if (rr.complete) {
    RemeshStats st = remesh_stats(mesh, rr.remesh, false);
    st.hausdorff_rel = rr.hausdorff_rel;  // the remesh's, through its grid of the input
    r.remesh_stats = stats_of(st);
  }
  // The input's topology from the Session's check (a whole analyze_mesh:
  // ~0.3 s at 416k vertices), else computed beside the diagram's quality.
  RemeshStats input;
  CvtQuality quality;
  tbb::parallel_invoke(
      [&] { input = derived.report ? mesh_topology_stats(mesh, *derived.report) : mesh_topology_stats(mesh); },
      [&] { quality = cvt_quality(mesh, rr.lloyd.label, rr.lloyd.sites); });
  r.input_stats = stats_of(input);
  r.stats_s = rr.hausdorff_s + seconds(t0);
  take_quality(quality, r);
  take_lloyd(mesh, rr.lloyd, r);
  r.complete = rr.complete;
  r.remesh = std::move(rr.remesh);
  r.remesh_site = std::move(rr.vertex_site);
  r.added_sites = rr.added_sites, r.repair_rounds = rr.repair_rounds, r.refinements = rr.refinements;
  r.lloyd_iterations = rr.lloyd_iterations;
  r.requested = rr.requested, r.delivered = rr.delivered, r.repair_sites = rr.repair_sites;
  r.removed_sites = rr.removed_sites, r.density_passes = rr.density_passes, r.geodesic_rounds = rr.geodesic_rounds;
  r.rebalance_rounds = rr.rebalance_rounds, r.single_triangles = rr.single_triangles;
  r.dual_mean_min_angle_deg = rr.dual_mean_min_angle_deg, r.dual_min_angle_deg = rr.dual_min_angle_deg;
  r.flips = rr.optimize.flips, r.smoothing_moves = rr.optimize.moves, r.boundary_moves = rr.optimize.boundary_moves;
  r.feature_edges = rr.feature_edges, r.feature_curves = rr.feature_curves;
  r.feature_corners = rr.feature_corners, r.feature_sites = rr.feature_sites;
  r.defects_before_repair = defects_of(rr.first_defects);
  r.defects_left = defects_of(rr.defects);
  r.remesh_factor_s = rr.factor_s, r.lloyd_s = rr.lloyd_s, r.repair_s = rr.repair_s, r.dual_s = rr.dual_s;
  r.optimize_s = rr.optimize_s;
  return r;
}

CvtResult cvt_result_of(CvtReport&& c) {
  CvtResult r;
  r.label.assign(c.label.begin(), c.label.end());
  r.empty_cells = c.lloyd_empty_cells;
  r.unreached = c.unreached;
  r.site_xyz = std::move(c.site_xyz);
  r.site_face = std::move(c.site_face);
  r.site_vertex = std::move(c.site_vertex);
  r.site_bary = std::move(c.site_bary);
  r.remeshed = c.complete;
  r.added_sites = c.added_sites;
  if (c.complete) {
    for (int32_t v = 0; v < c.remesh.num_vertices(); ++v)
      r.remesh_xyz.insert(r.remesh_xyz.end(), {c.remesh.x[v], c.remesh.y[v], c.remesh.z[v]});
    r.remesh_triangles.assign(c.remesh.face_vertices.begin(), c.remesh.face_vertices.end());
    r.remesh_site = std::move(c.remesh_site);
    const CvtMeshStats& st = c.remesh_stats;
    r.remesh_genus = st.genus;
    r.remesh_components = st.components;
    r.remesh_boundary_loops = st.boundary_loops;
    LOCUS_COPY_FIELDS(r, st, mean_min_angle_deg, min_angle_deg, pct_below_30_deg, hausdorff_rel);
  }
  return r;
}

void check_request(const CvtRequest& req) {
  check_count("--sites", req.sites, 1, 100000000);
  check_count("--iters", req.iters, 0, 1000000);
  check_range("--stop-energy", req.stop_energy, 0.0, 1.0);
  check_range("--anisotropy", req.anisotropy, 0.0, 1e6);
  if (req.solver != "local" && req.solver != "full")
    fail(ErrorCode::BadUsage, "--solver must be 'local' or 'full', got '" + req.solver + "'");
  parse_heat_time(req.t, "--t");
  centroid_time(req, nullptr);
  check_count("--fit-rings", req.fit_rings, 1, 4);
  check_range("--fit-sigma", req.fit_sigma, 0.0, 100.0);
  check_count("--repair-rounds", req.repair_rounds, 0, 1000);
  check_count("--refinements", req.refinements, 0, 4);
  check_count("--optimize", req.optimize, 0, 100);
  if (!(req.features >= 0 && req.features < 180))
    fail(ErrorCode::BadUsage, "--features must be a dihedral angle in degrees, 0 <= DEG < 180 (0: no features; got " +
                                  format_number(req.features) + ")");
  check_factor_cache_files({req.save, req.load});
  if (req.anisotropy > 0 && (!req.save.empty() || !req.load.empty()))
    fail(ErrorCode::BadUsage, "--save/--load cache the isotropic operator; not with --anisotropy");
  check_mesh_target("--labels", req.labels);
  check_mesh_target("--sites-out", req.sites_out);
}

// A refusal that depends on the mesh is bad input, like the mesh's own
// defects; too few sites for the components (every part needs one) are
// raised to their count and the note says so. More sites than vertices: the
// cells alone (no remesh) are sets of vertices and cannot hold them; a remesh
// runs Lloyd on a midpoint subdivision of the input with at least
// RemeshOptions::min_vertices_per_site vertices per site (cvt_remesh.cpp),
// refused when that subdivision would pass the memory limit.
int32_t check_sites(const CvtRequest& req, const Mesh& mesh, const MeshDerived& derived, int32_t components,
                    bool remesh, const RunContext& ctx) {
  const int64_t nv = mesh.num_vertices();
  if (req.sites > nv && !remesh)
    fail(ErrorCode::BadInput, mesh_name(mesh) + ": --sites " + std::to_string(req.sites) + " exceeds the " +
                                  std::to_string(nv) + " vertices of the mesh (the remesh takes more)");
  if (req.sites > nv) {
    // Vertex counts of the subdivisions: V' = V + E, E' = 2E + 3F, F' = 4F.
    int64_t v = nv, e = static_cast<int64_t>(derived.incidence.edges.e0.size()), f = mesh.num_faces();
    int times = 0;
    const double want = RemeshOptions{}.min_vertices_per_site * req.sites;
    for (; static_cast<double>(v) < want && times < 16; ++times) v += e, e = 2 * e + 3 * f, f *= 4;
    try {
      check_subdivision(mesh, times, ctx);
    } catch (const Error& err) {
      fail(err.code(), mesh_name(mesh) + ": --sites " + std::to_string(req.sites) + " on " + std::to_string(nv) +
                           " vertices needs " + std::to_string(times) + " midpoint subdivisions of the mesh: " +
                           err.what());
    }
    ctx.note(mesh_name(mesh) + ": --sites " + std::to_string(req.sites) + " exceeds the " + std::to_string(nv) +
             " vertices of the mesh: the cells run on its midpoint subdivision (" + std::to_string(times) +
             " times, " + std::to_string(v) + " vertices)");
  }
  if (req.sites >= components) return req.sites;
  ctx.note(mesh_name(mesh) + ": --sites " + std::to_string(req.sites) + " raised to " + std::to_string(components) +
           ": the mesh has " + std::to_string(components) + " connected components and every one needs a site");
  return components;
}

CvtReport cvt_command_on(const Mesh& mesh, const MeshDerived& derived, int32_t components, bool robust,
                         const CvtRequest& req, const HeatTime& ts, const HeatTime& tc, const RunContext& ctx,
                         MeshDerived* lend, Mesh* lend_mesh) {
  CvtRequest raised = req;
  raised.sites = check_sites(req, mesh, derived, components, true, ctx);
  // The cells' operator is factored here (isotropic): weighted in the progress
  // like kCvtFactorIterations Lloyd iterations (docs/shipping.md).
  const bool isotropic = req.anisotropy == 0;
  const CallProgress progress(ctx, isotropic, kCvtFactorIterations / (kCvtFactorIterations + req.iters + 1.0));
  FactorCacheReport cache;
  HeatDiffusion prepared;
  const auto t0 = std::chrono::steady_clock::now();
  // Without a centroid time of their own (which Lloyd's setup factors with the
  // same symbolic part) the factor is only solved with: its assembly map goes.
  const bool factor_once = tc.value == 0;
  // The incidence is not read from the operator's assembly to the dual
  // (incidence_loan.hpp): with `lend`, freed before the factor is allocated
  // (isotropic: Lloyd factors the lifted metric's operator itself).
  std::optional<IncidenceLoan> loan;
  if (lend && isotropic) loan.emplace(mesh, *lend);
  // The corners too (face_corner_loan.hpp), unless the factor cache hashes the
  // mesh or Lloyd assembles an operator of its own (a centroid time). Declared
  // after `loan`: on an error they are back before it rebuilds the incidence.
  std::optional<FaceCornerLoan> corners;
  if (lend_mesh && loan && factor_once && req.save.empty() && req.load.empty()) corners.emplace(*lend_mesh);
  const auto assembled = [&loan, &corners] {
    if (!loan) return;
    loan->release();
    loan->release_adjacency();  // the ordering and the factorization read the operator only
    if (corners) corners->release();
  };
  if (isotropic)
    prepared = command_heat_operator(mesh, robust, ts, {req.save, req.load}, progress.build(), cache, factor_once,
                                     &derived, assembled, /*borrow_mass=*/true);
  if (loan) loan->restore_adjacency();  // Lloyd's cell graph and neighborhoods read it
  const double prepare_s = seconds(t0);
  // The command's own operator: freed once the remesh's repair is done with it.
  CvtReport r = run_cvt(
      mesh, derived, raised, ts, tc, isotropic ? &prepared : nullptr, progress.query(),
      [&prepared] { prepared = HeatDiffusion{}; },
      [&loan, &corners] {
        if (!loan) return;  // the corners stay out through the repair (RemeshOptions::corners_needed)
        if (corners && loan->restore_reads_corners()) corners->restore();
        release_free_memory();  // Lloyd's geometry and cells, freed: not resident beside the rebuilt incidence
        loan->restore();
      },
      [&corners] {
        if (corners) corners->restore();
      });
  r.prepare_s = prepare_s;
  r.factor_cache = cache;
  r.requested = req.sites;  // as asked: `delivered` shows what the components needed
  progress.finish("remesh");
  return r;
}

CvtReport Session::cvt(const CvtRequest& req, const RunContext& ctx) const {
  check_request(req);
  const HeatTime ts = parse_heat_time(req.t, "--t");
  const HeatTime tc = centroid_time(req, &ctx);  // the deprecation note before any refusal of the mesh
  const std::shared_ptr<State> s = impl_->current();
  CvtReport r = cvt_needs_sheets(impl_->op)
                    ? cvt_on_sheets(s->mesh, s->robust, req, ts, tc, ctx)
                    : cvt_command_on(s->mesh, *s->derived, impl_->components, s->robust, req, ts, tc, ctx,
                                     impl_->exclusive ? exclusive_derived(*s) : nullptr,
                                     impl_->exclusive ? &s->mesh : nullptr);
  if (!req.labels.empty() || !req.sites_out.empty())
    write_cvt_files(req, r, s->polygons ? *s->polygons : s->mesh, {},
                    s->polygons ? triangle_polygon() : std::vector<int32_t>{});
  return r;
}

void write_cvt_files(const CvtRequest& req, const CvtReport& r, const Mesh& faces, WriteOptions carried,
                     const std::vector<int32_t>& triangle_polygon) {
  if (!req.labels.empty()) {
    auto& props = carried.vertex_properties;
    props.erase(std::remove_if(props.begin(), props.end(), [](const VertexProperty& p) { return p.name == "label"; }),
                props.end());
    if (carried.off_colour.empty()) carried.off_colour = "label";  // OFF shows the cells
    props.push_back({"label", VertexProperty::Type::Int, std::vector<double>(r.label.begin(), r.label.end())});
    write_mesh(req.labels, faces, carried);
  }
  if (req.sites_out.empty()) return;
  Mesh pts;
  WriteOptions wo;
  VertexProperty face{"face", VertexProperty::Type::Int, {}}, vert{"vertex", VertexProperty::Type::Int, {}};
  VertexProperty b[3] = {{"b0", VertexProperty::Type::Double, {}}, {"b1", VertexProperty::Type::Double, {}},
                         {"b2", VertexProperty::Type::Double, {}}};
  VertexProperty polygon{"polygon", VertexProperty::Type::Int, {}};
  for (size_t k = 0; k < r.site_face.size(); ++k) {
    pts.add_vertex(r.site_xyz[3 * k], r.site_xyz[3 * k + 1], r.site_xyz[3 * k + 2]);
    face.values.push_back(r.site_face[k]);
    vert.values.push_back(r.site_vertex[k]);
    for (int c = 0; c < 3; ++c) b[c].values.push_back(r.site_bary[3 * k + c]);
    if (!triangle_polygon.empty())
      polygon.values.push_back(r.site_face[k] < 0 ? -1 : triangle_polygon[r.site_face[k]]);
  }
  wo.vertex_properties = {face, vert, b[0], b[1], b[2]};
  if (!triangle_polygon.empty()) wo.vertex_properties.push_back(std::move(polygon));
  write_mesh(req.sites_out, pts, wo);
}

}  // namespace locus
