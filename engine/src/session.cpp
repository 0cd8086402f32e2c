// locus::Session (engine/include/locus/session.hpp): a mesh, its derived data
// cached per key, and the queries of the pipelines on top of them.
//
// The caches and their concurrency design: engine/src/session_state.hpp. The
// queries of the later pipelines are in session_<pipeline>.cpp.
#include "locus/session.hpp"
#include "session_state.hpp"
#include "cvt_sheets.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <exception>
#include <future>
#include <limits>
#include <map>
#include <mutex>
#include <new>
#include <utility>

#include <tbb/parallel_invoke.h>

#include "locus/kernels/update/factor_update.hpp"
#include "locus/kernels/mesh/mesh_derived.hpp"
#include "locus/kernels/mesh/mesh_operators.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/kernels/mesh/patch_grower.hpp"
#include "locus/kernels/mesh/mesh_defects.hpp"
#include "locus/kernels/mesh/robust_heat_operators.hpp"
#include "locus/kernels/order/ordering.hpp"
#include "locus/kernels/solve/solve_full.hpp"
#include "locus/kernels/solve/solve_plan.hpp"
#include "locus/kernels/solve/solve_sparse.hpp"
#include "locus/kernels/factor/supernodal_factor.hpp"
#include "locus/kernels/symbolic/symbolic_factor.hpp"
#include "locus/error.hpp"
#include "locus/pipelines/voronoi/cvt_lloyd.hpp"
#include "locus/pipelines/deform/deform.hpp"
#include "locus/pipelines/geodesic/heat_geodesic.hpp"
#include "locus/pipelines/geodesic/logmap.hpp"

namespace locus {
namespace session_detail {


// Checks the mesh (once per positions) and derives its data; d.checked records the check.
std::shared_ptr<const MeshDerived> check_and_derive(const Mesh& m, OperatorChoice choice, OperatorReport* out) {
  validate_mesh_arrays(m);
  if (m.num_vertices() == 0) fail(ErrorCode::BadInput, mesh_name(m) + ": the mesh has no vertices");
  if (m.num_faces() == 0) fail(ErrorCode::BadInput, mesh_name(m) + ": the mesh has no faces");
  MeshRequirements req;
  req.triangles = req.manifold = req.no_degenerate_faces = req.no_unreferenced_vertices = true;
  req.finite_coordinates = true;
  // One edge incidence for the checks, the derived data and (through it) every
  // operator; the checks and the rest of the derived data read only it and the
  // mesh, so they run side by side. The checks' error wins (it names the offender).
  auto d = std::make_shared<MeshDerived>();
  d->incidence = edge_incidence(m);
  MeshReport report;
  std::exception_ptr derive_error;
  tbb::parallel_invoke([&] { report = analyze_mesh(m, d->incidence); },
                       [&] {
                         try {
                           complete_derived(m, *d);
                         } catch (...) {
                           derive_error = std::current_exception();
                         }
                       });
  if (choice != OperatorChoice::Cotan) {
    // What every operator needs first; then the defects, from the same pass.
    MeshRequirements base = req;
    base.manifold = base.no_degenerate_faces = base.no_unreferenced_vertices = false;
    check_requirements(m, base, report);
    if (derive_error) std::rethrow_exception(derive_error);
    const OperatorReport op = choose_operator_from(m, d->incidence, report, choice);
    if (out) *out = op;
    if (op.robust) {
      d->checked = base;
      d->report = report;
      drop_edge_corners(d->incidence);
      return d;
    }
  }
  check_requirements(m, req, report);
  if (derive_error) std::rethrow_exception(derive_error);
  d->checked = req;
  d->report = report;
  // The checks were the last to read the corners of each edge: the operators,
  // Lloyd and the dual read the edges and corner_edge, and what needs them
  // again (boundary loops, feature edges, a later report) rebuilds them.
  drop_edge_corners(d->incidence);
  return d;
}

std::shared_ptr<const RobustOperators> robust_operators(State& s, const RunContext& ctx) {
  return s.robust_ops.get(0, ctx, [&] {
    ctx.report(0.0, "robust Laplacian");
    return std::make_shared<const RobustOperators>(robust_laplacian(s.mesh));
  });
}

std::shared_ptr<const HeatGeodesic> geodesic_engine(State& s, const HeatQuery& q, const RunContext& ctx) {
  if (!s.robust) {
    const std::shared_ptr<const HeatLogMap> e = engine(s, q, ctx);
    return std::shared_ptr<const HeatGeodesic>(e, &e->geodesic());
  }
  return robust_geodesic_engine(s, q, ctx);
}

std::shared_ptr<const HeatGeodesic> robust_geodesic_engine(State& s, const HeatQuery& q, const RunContext& ctx) {
  const double tf = heat_method_t_factor(q);
  check_heat_method_time(q, tf);
  return s.robust_engines.get(bits_of(tf), ctx, [&] {
    ctx.report(0.0, "prepare heat method (robust operator)");
    const std::shared_ptr<const RobustOperators> R = robust_operators(s, ctx);
    HeatGeodesicOptions o;
    o.t_factor = tf;
    // The last resort of a defective or badly shaped mesh: a few vertices a
    // twentieth of an edge below zero are the Poisson step's discretization
    // error (cheese.off: 6e-3 h), set to 0 and reported.
    o.dip_tolerance_h = 0.05;
    auto e = std::make_shared<const HeatGeodesic>(s.mesh, *R, o, ctx, s.derived.get());
    s.counters->engines.fetch_add(1);
    ctx.report(1.0, "prepare heat method (robust operator)");
    return e;
  });
}

std::vector<char> referenced_vertices(const State& s) {
  if (!s.robust) return {};
  std::vector<char> used(static_cast<size_t>(s.mesh.num_vertices()), 0);
  for (int32_t v : s.mesh.face_vertices) used[v] = 1;
  if (std::find(used.begin(), used.end(), 0) == used.end()) return {};
  return used;
}

bool geodesic_engine_cached(State& s, const HeatQuery& q) {
  const uint64_t key = bits_of(heat_method_t_factor(q));
  return s.robust ? s.robust_engines.contains(key) : s.engines.contains(key);
}

void check_vertex(const State& s, int64_t v, const char* what) {
  const int32_t n = s.mesh.num_vertices();
  if (v < 0 || v >= n)
    fail(ErrorCode::BadUsage, std::string(what) + " " + std::to_string(v) + " is not a vertex of " +
                                  mesh_name(s.mesh) + " (" + std::to_string(n) + " vertices, ids 0.." +
                                  std::to_string(n - 1) + ")");
}

void check_t_factor(double t_factor) {
  if (!(t_factor > 0) || !std::isfinite(t_factor))
    fail(ErrorCode::BadUsage, "t_factor must be a finite positive number (got " + std::to_string(t_factor) + ")");
}

void check_heat_method_time(const HeatQuery& q, double t_factor) {
  check_t_factor(t_factor);
  if (q.t != 0.0) fail(ErrorCode::BadUsage, "the heat method (geodesic distance, log map) takes t_factor, not an absolute t");
}

std::shared_ptr<const HeatLogMap> engine(State& s, const HeatQuery& q, const RunContext& ctx) {
  const double tf = heat_method_t_factor(q);
  check_heat_method_time(q, tf);
  if (s.robust)  // the log map's frames and transport need one tangent plane per vertex
    fail(ErrorCode::BadInput, "the log map needs a manifold mesh without degenerate faces, and " + mesh_name(s.mesh) +
                                  " runs on the robust operator; geodesic distance and the diffusion queries answer on it");
  return s.engines.get(bits_of(tf), ctx, [&] {
    ctx.report(0.0, "prepare heat method");
    LogMapOptions o;
    o.geodesic.t_factor = tf;
    auto e = std::make_shared<const HeatLogMap>(s.mesh, o, ctx, s.derived.get());
    s.counters->engines.fetch_add(1);
    ctx.report(1.0, "prepare heat method");
    return e;
  });
}

std::shared_ptr<const SymbolicFactor> symbolic_for(State& s, const CscMatrix& A, const RunContext& ctx) {
  return s.symbolic->by_pattern.get({pattern_hash(A), A.nnz()}, ctx, [&] {
    // The ordering HeatGeodesic uses (the same factor, bit for bit), inside the
    // first 80% of the caller's progress as there.
    const Ordering ord = order_matrix(A, {}, ctx.sub(0.0, 0.75));
    auto S = analyze(A, ord, {}, ctx.sub(0.75, 0.80));
    s.counters->symbolic.fetch_add(1);
    return S;
  });
}

std::shared_ptr<const NumericFactor> heat_factor(State& s, double t_factor, const RunContext& ctx) {
  check_t_factor(t_factor);
  // The factor inside the diffusion cache: one factorization per t serves every diffusion pipeline.
  const std::shared_ptr<const HeatDiffusion> H = diffusion(s, HeatQuery{t_factor, 0.0}, ctx);
  return std::shared_ptr<const NumericFactor>(H, &H->factor);
}

// The cells' operator of cvt_lloyd (its default t = kLloydTFactor h^2), built once per positions: later
// cvt calls skip ordering and factoring.
std::shared_ptr<const HeatDiffusion> cvt_heat(State& s, const RunContext& ctx) {
  return s.cvt_heat.get(0, ctx, [&] {
    ctx.report(0.0, "factor heat operator (cvt)");
    std::shared_ptr<const HeatDiffusion> H;
    if (s.robust) {  // the robust operator's M - tL at cvt_lloyd's default time
      const std::shared_ptr<const RobustOperators> R = robust_operators(s, ctx);
      const double t = kLloydTFactor * s.h * s.h;
      H = std::make_shared<const HeatDiffusion>(
          prepare_heat_diffusion(robust_heat_operator(*R, t), HostVector<double>(R->mass), s.h, t, ctx));
    } else {
      H = std::make_shared<const HeatDiffusion>(prepare_heat_diffusion(s.mesh, *s.derived, kLloydTFactor, 0.0, ctx));
    }
    s.counters->numeric.fetch_add(1);
    ctx.report(1.0, "factor heat operator (cvt)");
    return H;
  });
}

// Log map patches: geodesic disks (patch_grower.hpp), on the derived adjacency.
std::shared_ptr<const PatchGrower> grower(State& s, const RunContext& ctx) {
  return s.grower.get(0, ctx, [&] {
    return std::make_shared<const PatchGrower>(prepare_patch_grower(s.mesh, s.derived->adjacency));
  });
}

// `derived`: of `mesh`, from check_and_derive.
std::shared_ptr<State> make_state(Mesh mesh, std::shared_ptr<const MeshDerived> derived, int64_t version,
                                  std::shared_ptr<SymbolicCache> symbolic, std::shared_ptr<Counters> counters) {
  auto s = std::make_shared<State>();
  s->mesh = std::move(mesh);
  s->derived = std::move(derived);
  s->h = s->derived->h;
  s->version = version;
  s->symbolic = std::move(symbolic);
  s->counters = std::move(counters);
  return s;
}

}  // namespace session_detail

using namespace session_detail;


Session::Session(Mesh mesh) : Session(std::move(mesh), SessionOptions{}) {}

Session::Session(Mesh mesh, const SessionOptions& opt) : impl_(std::make_unique<Impl>()) {
  std::shared_ptr<const Mesh> polygons;
  impl_->npoly = mesh.num_faces();
  if (!mesh.is_triangle_mesh()) {  // CSR faces that are all triangles (no f0/f1/f2 given) are a triangle mesh
    validate_mesh_arrays(mesh);
    mesh.rebuild_triangle_arrays();
  }
  if (!mesh.is_triangle_mesh()) {  // session.hpp "Polygon meshes": triangulated once, vertices kept
    Mesh triangles = triangulate_for_session(mesh, impl_->face_of);
    impl_->polygon_edges = static_cast<int64_t>(unique_edges(mesh).e0.size());
    polygons = std::make_shared<const Mesh>(std::move(mesh));
    mesh = std::move(triangles);
  }
  impl_->op.asked = opt.mesh_operator;
  impl_->exclusive = opt.exclusive;
  std::shared_ptr<const MeshDerived> derived = check_and_derive(mesh, opt.mesh_operator, &impl_->op);
  impl_->nv = mesh.num_vertices();
  impl_->nf = mesh.num_faces();
  impl_->components = derived->components;
  impl_->state = make_state(std::move(mesh), std::move(derived), 0, std::make_shared<SymbolicCache>(),
                            std::make_shared<Counters>());
  impl_->state->polygons = std::move(polygons);
  impl_->state->robust = impl_->op.robust;
  impl_->robust_fallback = !impl_->op.robust && (opt.mesh_operator == OperatorChoice::Auto ||
                                                 (opt.mesh_operator == OperatorChoice::Cotan && opt.cotan_chosen_by_auto));
}

Session Session::from_file(const std::string& path, const ReadOptions& opt) { return Session(read_mesh(path, opt)); }
Session Session::from_file(const std::string& path, const ReadOptions& opt, const SessionOptions& so) {
  return Session(read_mesh(path, opt), so);
}

Session::Session(const MeshView& view) : Session(mesh_from_view(view)) {}
Session::Session(const PolygonMeshView& view) : Session(mesh_from_view(view)) {}
Session::Session(const MeshView& view, const SessionOptions& opt) : Session(mesh_from_view(view), opt) {}
Session::Session(const PolygonMeshView& view, const SessionOptions& opt) : Session(mesh_from_view(view), opt) {}

OperatorReport Session::operator_report() const { return impl_->op; }

Session::Session(Session&&) noexcept = default;
Session& Session::operator=(Session&&) noexcept = default;
Session::~Session() = default;

int32_t Session::num_vertices() const { return impl_->nv; }
int32_t Session::num_faces() const { return impl_->nf; }
double Session::mean_edge_length() const { return impl_->current()->h; }
Mesh Session::mesh() const { return impl_->current()->mesh; }
bool Session::has_polygons() const { return !impl_->face_of.empty(); }
Mesh Session::polygons() const {
  const std::shared_ptr<State> s = impl_->current();
  return s->polygons ? *s->polygons : s->mesh;
}
int32_t Session::num_polygons() const { return impl_->npoly; }
std::vector<int32_t> Session::triangle_polygon() const {
  if (has_polygons()) return impl_->face_of;
  std::vector<int32_t> id(static_cast<size_t>(impl_->nf));
  for (int32_t f = 0; f < impl_->nf; ++f) id[f] = f;
  return id;
}

void Session::prepare_heat(const HeatQuery& q, const RunContext& ctx) const {
  const std::shared_ptr<State> s = impl_->current();
  if (s->polygons && !s->robust)
    polygon_engine(*s, q, ctx);
  else
    geodesic_engine(*s, q, ctx);
}

void Session::geodesic_distance(int32_t source, View<double> out, const HeatQuery& q,
                                const RunContext& ctx) const {
  const std::shared_ptr<State> s = impl_->current();
  check_vertex(*s, source, "geodesic_distance: source");
  if (out.size() != static_cast<size_t>(impl_->nv))
    fail(ErrorCode::BadUsage, "geodesic_distance: output has " + std::to_string(out.size()) + " entries, expected " +
                                  std::to_string(impl_->nv));
  if (s->polygons && !s->robust) return polygon_geodesic(*s, source, out, q, ctx);
  const CallProgress progress(ctx, !geodesic_engine_cached(*s, q));
  const auto g = geodesic_engine(*s, q, progress.build());
  ctx.check_cancel();
  HeatGeodesicWorkspace ws;
  g->query_full(source, out, ws);
  // The solver's +infinity (another connected component, no path) is "no
  // value": NaN, as in every output format and the C API (README "Output
  // formats"); a NaN from the solver itself never is an answer.
  for (int32_t i = 0; i < impl_->nv; ++i) {
    if (std::isnan(out[i]))
      fail(ErrorCode::Numerical, "geodesic_distance: the distance from vertex " + std::to_string(source) +
                                     " is NaN at vertex " + std::to_string(i) + " (t = " +
                                     std::to_string(g->time()) + ")");
    if (std::isinf(out[i])) out[i] = std::numeric_limits<double>::quiet_NaN();
  }
  progress.finish("geodesic distance");
}

std::vector<double> Session::geodesic_distance(int32_t source, const HeatQuery& q, const RunContext& ctx) const {
  std::vector<double> d(static_cast<size_t>(impl_->nv));
  geodesic_distance(source, d, q, ctx);
  return d;
}

void session_detail::check_map_finite(int32_t center, const LogMapResult& r) {
  for (size_t p = 0; p < r.patch.size(); ++p)
    if (!std::isfinite(r.u[p]) || !std::isfinite(r.v[p]))
      fail(ErrorCode::Numerical, "logmap: the map around vertex " + std::to_string(center) +
                                     " is not finite at vertex " + std::to_string(r.patch[p]));
}

LogMapResult Session::logmap(int32_t center, double fraction, const HeatQuery& q, const RunContext& ctx) const {
  const std::shared_ptr<State> s = impl_->current();
  check_vertex(*s, center, "logmap: center");
  if (!(fraction > 0 && fraction <= 1))
    fail(ErrorCode::BadUsage, "logmap: fraction must be in (0, 1] (got " + std::to_string(fraction) + ")");
  const int32_t n = impl_->nv;
  const int32_t count = std::clamp<int32_t>(static_cast<int32_t>(std::lround(fraction * n)), 1, n);
  if (s->polygons) return polygon_logmap(*s, center, count, q, ctx);
  const CallProgress progress(ctx, !s->engines.contains(bits_of(heat_method_t_factor(q))));
  const auto e = engine(*s, q, progress.build());
  const auto g = grower(*s, ctx);
  ctx.check_cancel();
  LogMapResult r;
  PatchWorkspace pws;
  grow_patch_vertices(*g, center, geodesic_disk(count), pws, r.patch);
  const size_t k = r.patch.size();
  r.distance.resize(k), r.angle.resize(k), r.u.resize(k), r.v.resize(k);
  LogMapWorkspace ws;
  e->query(center, r.patch, {r.distance, r.angle, r.u, r.v}, ws);
  check_map_finite(center, r);
  progress.finish("log map");
  return r;
}

std::vector<double> Session::heat_values(ConstView<int32_t> sources, ConstView<int32_t> targets,
                                         const HeatQuery& q, const RunContext& ctx) const {
  const std::shared_ptr<State> s = impl_->current();
  for (size_t k = 0; k < sources.size(); ++k)
    check_vertex(*s, sources[k], ("heat_values: source " + std::to_string(k) + " is vertex").c_str());
  for (size_t k = 0; k < targets.size(); ++k)
    check_vertex(*s, targets[k], ("heat_values: target " + std::to_string(k) + " is vertex").c_str());
  const size_t ns = sources.size(), nt = targets.size();
  std::vector<double> out(ns * nt);
  if (ns == 0 || nt == 0) return out;
  const CallProgress progress(ctx, !diffusion_cached(*s, HeatQuery{diffusion_t_factor(q), 0.0}));
  const auto F = heat_factor(*s, diffusion_t_factor(q), progress.build());
  // One exact plan per batch of 8 sources, wanted = the distinct targets.
  std::vector<int32_t> wanted(targets.begin(), targets.end());
  std::sort(wanted.begin(), wanted.end());
  wanted.erase(std::unique(wanted.begin(), wanted.end()), wanted.end());
  std::vector<size_t> target_row(nt);
  for (size_t k = 0; k < nt; ++k)
    target_row[k] = static_cast<size_t>(std::lower_bound(wanted.begin(), wanted.end(), targets[k]) - wanted.begin());
  SolveWorkspace ws;
  std::vector<int32_t> support;
  std::vector<double> rhs, vals;
  const size_t nbatch = (ns + kLanes - 1) / kLanes;
  for (size_t b = 0; b < nbatch; ++b) {
    ctx.check_cancel();
    const size_t first = b * kLanes, lanes = std::min<size_t>(kLanes, ns - first);
    support.assign(sources.begin() + first, sources.begin() + first + lanes);
    std::sort(support.begin(), support.end());
    support.erase(std::unique(support.begin(), support.end()), support.end());
    const SolvePlan plan = plan_subset_solve(*F->symbolic, support, wanted);
    rhs.assign(support.size() * kLanes, 0.0);
    for (size_t l = 0; l < lanes; ++l) {
      const size_t pos = std::lower_bound(support.begin(), support.end(), sources[first + l]) - support.begin();
      rhs[pos * kLanes + l] = 1.0;
    }
    vals.assign(wanted.size() * kLanes, 0.0);
    solve_planned8(*F, plan, rhs, vals, ws);
    for (size_t l = 0; l < lanes; ++l)
      for (size_t k = 0; k < nt; ++k) out[(first + l) * nt + k] = vals[target_row[k] * kLanes + l];
    progress.query().report(static_cast<double>(b + 1) / static_cast<double>(nbatch), "heat values");
  }
  return out;
}

CvtResult Session::cvt(int32_t sites, int32_t iterations, uint64_t seed, const RunContext& ctx, bool remesh) const {
  // The command's checks (session_cvt_command.cpp), on the command's request.
  CvtRequest q;
  q.sites = sites;
  q.iters = iterations;
  q.seed = seed;
  check_request(q);
  const std::shared_ptr<State> s = impl_->current();
  if (cvt_needs_sheets(impl_->op)) {  // the command's path, which cuts the mesh
    if (!remesh) q.repair_rounds = 0, q.optimize = 0;
    CvtResult r = cvt_result_of(cvt(q, ctx));
    if (!remesh) r.remeshed = false, r.remesh_xyz.clear(), r.remesh_triangles.clear(), r.remesh_site.clear();
    return r;
  }
  q.sites = check_sites(q, s->mesh, *s->derived, impl_->components, remesh, ctx);
  LloydOptions o;
  o.sites = q.sites;
  o.iterations = iterations;
  o.seed = seed;
  // One monotone progress fraction: the cells' operator (when not cached yet)
  // weighted like kCvtFactorIterations Lloyd iterations (docs/shipping.md), then the iterations.
  const CallProgress progress(ctx, !s->cvt_heat.contains(0), kCvtFactorIterations / (kCvtFactorIterations + iterations + 1.0));
  const std::shared_ptr<const HeatDiffusion> H = cvt_heat(*s, progress.build());
  o.prepared = H.get();  // kLloydTFactor = cvt_lloyd's default: the same operator, bit for bit
  const RunContext& rest = progress.query();
  if (remesh) {
    // The command's call sequence (session_cvt_command.cpp) on the kept operator.
    CvtResult r = cvt_result_of(
        run_cvt(s->mesh, *s->derived, q, HeatTime{kLloydTFactor, true}, HeatTime{0.0, true}, H.get(), rest));
    progress.finish("remesh");
    return r;
  }
  LloydResult lr = cvt_lloyd(s->mesh, *s->derived, o, rest);  // the mesh was checked once, by the Session
  CvtResult r;
  r.label = std::move(lr.label);
  r.empty_cells = lr.empty_cells;
  r.unreached = lr.unreached;
  for (const SurfacePoint& p : lr.sites) {
    const std::array<double, 3> x = surface_point_position(s->mesh, p);
    r.site_xyz.insert(r.site_xyz.end(), x.begin(), x.end());
    r.site_face.push_back(p.face);
    r.site_vertex.push_back(p.face < 0 ? p.vertex : -1);
    r.site_bary.insert(r.site_bary.end(), p.bary.begin(), p.bary.end());
  }
  progress.finish("lloyd");
  return r;
}

DeformResult Session::deform(const DeformRequest& req, const RunContext& ctx) const {
  // The command's computation (session_deform_command.cpp) with the older fields.
  if (!(req.roi_fraction > 0 && req.roi_fraction <= 1))
    fail(ErrorCode::BadUsage, "deform: roi_fraction must be in (0, 1] (got " + std::to_string(req.roi_fraction) + ")");
  const DeformCommandRequest q{.roi_seed = req.roi_seed, .roi_fraction = req.roi_fraction, .handle = req.handle_vertex,
                               .handle_ring = req.handle_ring, .offset = req.offset,
                               .energy = req.energy == DeformEnergyKind::Bilaplacian ? "bilaplacian" : "laplacian"};
  DeformCommandReport c = deform(q, ctx);
  return DeformResult{.xyz = std::move(c.xyz), .roi_size = c.roi_vertices, .free_size = c.free_vertices,
                      .columns_updated_fraction = c.columns_updated_fraction, .refinement_steps = c.refinement_steps,
                      .residual = c.residual};
}

void Session::set_positions(ConstView<double> xyz) {
  const int32_t n = impl_->nv;
  if (xyz.size() != 3 * static_cast<size_t>(n))
    fail(ErrorCode::BadUsage, "set_positions: " + std::to_string(xyz.size()) + " coordinates, expected 3 * " +
                                  std::to_string(n));
  for (size_t k = 0; k < xyz.size(); ++k)
    if (!std::isfinite(xyz[k]))
      fail(ErrorCode::BadInput, "set_positions: vertex " + std::to_string(k / 3) + " has a non-finite coordinate");
  const std::shared_ptr<State> old = impl_->current();
  Mesh m = old->mesh;
  for (int32_t i = 0; i < n; ++i) {
    m.x[i] = xyz[3 * static_cast<size_t>(i)];
    m.y[i] = xyz[3 * static_cast<size_t>(i) + 1];
    m.z[i] = xyz[3 * static_cast<size_t>(i) + 2];
  }
  std::shared_ptr<const Mesh> polygons = old->polygons ? polygons_moved(*old->polygons, m) : nullptr;
  OperatorReport op;
  std::shared_ptr<const MeshDerived> derived =  // zero-area faces (the cotan operator's)
      check_and_derive(m, old->robust ? OperatorChoice::Robust : OperatorChoice::Cotan, &op);
  std::lock_guard<std::mutex> lock(impl_->mu);
  // Versions count calls; concurrent set_positions calls are serialized here (the last one wins).
  std::shared_ptr<State> next = make_state(std::move(m), std::move(derived), impl_->state->version + 1,
                                           impl_->state->symbolic, impl_->state->counters);
  next->polygons = std::move(polygons);  // complete before queries can see it
  next->robust = old->robust;
  impl_->state = std::move(next);
}

SessionStats Session::stats() const {
  const std::shared_ptr<State> s = impl_->current();
  SessionStats st;
  st.symbolic_analyses = s->counters->symbolic.load();
  st.numeric_factorizations = s->counters->numeric.load();
  st.heat_engines = s->counters->engines.load();
  st.deform_operators = s->counters->deform.load();
  st.positions_version = s->version;
  return st;
}

}  // namespace locus
