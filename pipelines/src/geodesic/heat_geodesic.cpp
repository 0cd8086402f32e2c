// Heat geodesic distance, whole-mesh and localized (pipelines/include/locus/pipelines/geodesic/heat_geodesic.hpp;
// thesis §6.4.1-6.4.2, eqs. 6.3-6.6). The region a localized query works on is
// built in heat_geodesic_region.cpp; what the method refuses (needles, too long
// a time, memory, distances that are no answer) is in heat_geodesic_limits.cpp.
#include "locus/pipelines/geodesic/heat_geodesic.hpp"
#include "heat_geodesic_limits.hpp"
#include "locus/core/host_allocator.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "locus/kernels/simd/log_array.hpp"
#include "locus/kernels/mesh/mesh_derived.hpp"
#include "locus/kernels/mesh/mesh_operators.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/kernels/mesh/robust_heat_operators.hpp"
#include "locus/kernels/order/ordering.hpp"
#include "locus/kernels/solve/solve_full.hpp"
#include "locus/kernels/solve/solve_plan.hpp"
#include "locus/kernels/symbolic/symbolic_factor.hpp"
#include "locus/kernels/parallel/thread_cpu_time.hpp"
#include "locus/error.hpp"
#include "locus/kernels/parallel/cancel_point.hpp"

#include <tbb/parallel_invoke.h>

namespace locus {

using namespace heat_geodesic_limits;

namespace {

// Where the constructor's phases begin in its progress, by their measured
// shares of its time at 416k vertices (docs/shipping.md): operators, ordering,
// symbolic analysis, then the factorizations.
constexpr double kOrderBegin = 0.15, kAnalyzeBegin = 0.74, kFactorBegin = 0.78, kPoissonBegin = 0.89;

void check_vertex(int32_t v, int32_t n, const char* what) {
  if (v < 0 || v >= n)
    fail(ErrorCode::BadUsage, std::string(what) + " " + std::to_string(v) + " is not a vertex (the mesh has " +
                                  std::to_string(n) + " vertices)");
}

// Normalized negative gradient of the heat in face k (eq. 6.5); zero where the
// heat is flat (underflow), so such faces carry no direction.
// l* = log h* (or NaN where h <= 0, computed once per vertex), used when all three are finite.
inline void unit_direction(const TriangleGradients& g, int32_t k, double h0, double h1, double h2, const double* l,
                           double X[3]) {
  if (l && std::isfinite(l[0] + l[1] + l[2])) g.gradient(k, l[0], l[1], l[2], X);
  else g.gradient(k, h0, h1, h2, X);
  const double len = std::sqrt(X[0] * X[0] + X[1] * X[1] + X[2] * X[2]);
  const double s = len > 0.0 && std::isfinite(len) ? -1.0 / len : 0.0;
  for (int c = 0; c < 3; ++c) X[c] *= s;
}

// A_k grad(phi_s) . X for the three corners of face k.
inline void corner_divergence(const TriangleGradients& g, int32_t k, const double X[3], double out[3]) {
  const double* b = g.basis.data() + 9 * static_cast<int64_t>(k);
  const double a = g.area[k];
  for (int s = 0; s < 3; ++s) out[s] = a * (b[3 * s] * X[0] + b[3 * s + 1] * X[1] + b[3 * s + 2] * X[2]);
}

// A += beta (M_consistent - M_lumped) on A's pattern (lower CSC, diagonal first
// in each column). Per triangle of area a: consistent mass a/6 on each corner's
// diagonal and a/12 per edge, lumped a/3 on the diagonal; rows sums agree, so
// the total mass is unchanged. Why: on a lattice of spacing h the plane waves
// exp(k . x) of (M - t L_C) have |k|^2 = (1 - c h^2 / t) / t with lumped mass and
// (1 + c h^2 / t) / t with the consistent one (1-D: c = 1/12). At t = h^2 that
// term is a few percent and varies with the local edge length and shape, so the
// decay rate per unit length varies over the mesh and the heat's paths bend
// (icosphere: angle errors that grow with the distance, harmonic 2 at the
// midpoints of the icosahedron's edges); the half-and-half blend cancels it.
void blend_mass(const Mesh& m, double beta, CscMatrix& A) {
  if (beta == 0.0) return;
  auto at = [&](int32_t r, int32_t c) -> double& {
    if (r < c) std::swap(r, c);
    for (int64_t q = A.colptr[c]; q < A.colptr[c + 1]; ++q)
      if (A.rowind[q] == r) return A.values[q];
    fail(ErrorCode::Internal, "blend_mass: edge (" + std::to_string(r) + ", " + std::to_string(c) + ") not in the pattern");
  };
  for (int32_t f = 0; f < m.num_faces(); ++f) {
    cancel_point(f);
    const int32_t v[3] = {m.f0[f], m.f1[f], m.f2[f]};
    const double ux = m.x[v[1]] - m.x[v[0]], uy = m.y[v[1]] - m.y[v[0]], uz = m.z[v[1]] - m.z[v[0]];
    const double wx = m.x[v[2]] - m.x[v[0]], wy = m.y[v[2]] - m.y[v[0]], wz = m.z[v[2]] - m.z[v[0]];
    const double cx = uy * wz - uz * wy, cy = uz * wx - ux * wz, cz = ux * wy - uy * wx;
    const double area = 0.5 * std::sqrt(cx * cx + cy * cy + cz * cz);
    for (int s = 0; s < 3; ++s) {
      at(v[s], v[s]) -= beta * area / 6;
      at(v[s], v[(s + 1) % 3]) += beta * area / 12;
    }
  }
}

}  // namespace

namespace {
MeshRequirements heat_requirements() {
  MeshRequirements req;
  req.triangles = req.manifold = req.no_degenerate_faces = req.no_unreferenced_vertices = true;
  return req;
}
}  // namespace

CscMatrix HeatGeodesic::poisson_operator(const Mesh& m, const HeatGeodesicOptions& opt, const EdgeIncidence* inc) {
  // regularized_laplacian's eps is rel * trace(-L_C) / trace(M); divided by n
  // it is poisson_rel * mean(diag(-L_C)) / area (see heat_geodesic.hpp).
  return regularized_laplacian(m, opt.poisson_rel / std::max<int32_t>(1, m.num_vertices()), inc);
}

void HeatGeodesic::prepare(const Mesh& m, const MeshDerived* given, const RobustOperators* robust) {
  const HeatGeodesicOptions& opt = opt_;
  if (!(opt.t_factor > 0) || !std::isfinite(opt.t_factor))
    fail(ErrorCode::BadUsage, "heat geodesic: t_factor must be a finite positive number (got " +
                                  std::to_string(opt.t_factor) + ")");
  check_time(opt.t_factor);
  if (!(opt.poisson_rel > 0) || !std::isfinite(opt.poisson_rel))
    fail(ErrorCode::BadUsage, "heat geodesic: poisson_rel must be a finite positive number");
  if (!(opt.mass_blend >= 0 && opt.mass_blend <= 1))
    fail(ErrorCode::BadUsage, "heat geodesic: mass_blend must be in [0, 1] (got " + std::to_string(opt.mass_blend) + ")");
  // The robust operator's intrinsic triangles take any triangle soup; the
  // cotan operator's extrinsic ones need a manifold without needles.
  const MeshRequirements req = heat_requirements();
  if (!robust && (!given || !requirements_checked(*given, req))) check_requirements(m, req);
  if (given) check_derived_of(*given, m, "heat geodesic");
  if (!robust) check_needles(m);
  if (m.num_vertices() == 0) fail(ErrorCode::BadInput, mesh_name(m) + ": the mesh has no vertices");
  MeshDerived own;
  if (!given) own = derive_mesh(m);  // edges once: components, h (gradients' threshold and t)
  const MeshDerived& d = given ? *given : own;
  num_components_ = d.components;
  component_.assign(d.component.begin(), d.component.end());
  grad_ = robust ? intrinsic_triangle_gradients(robust->triangulation) : triangle_gradients(m, d.h);
  // Corner records in vertex-face order (see build_region).
  vf_corners_.resize(4 * grad_.vf_faces.size());
  for (size_t q = 0; q < grad_.vf_faces.size(); ++q) {
    for (int s = 0; s < 3; ++s) vf_corners_[4 * q + s] = grad_.tri[3 * static_cast<int64_t>(grad_.vf_faces[q]) + s];
    vf_corners_[4 * q + 3] = grad_.vf_faces[q];
  }
  h_ = d.h;
  t_ = opt.t_factor * h_ * h_;
}

double HeatGeodesic::operators(const Mesh& m, const HeatGeodesicOptions& opt, CscMatrix& heat, CscMatrix& poisson) {
  const double h = locus::mean_edge_length(m);
  const double t = opt.t_factor * h * h;
  heat = heat_operator(m, t);
  blend_mass(m, opt.mass_blend, heat);
  normalize_heat_operator(heat);
  poisson = poisson_operator(m, opt);
  return t;
}

HeatGeodesic::HeatGeodesic(const Mesh& m, const HeatGeodesicOptions& opt, const RunContext& ctx,
                           const MeshDerived* derived)
    : opt_(opt) {
  // The steps below take 0.1-0.3 s each at 416k vertices: their loops are
  // cancel points (cancel_point.hpp), and each step's end reports too.
  const RunContext operators_ctx = ctx.sub(0.0, kOrderBegin);
  // Beside the ordering (below) the operators' steps only poll the cancel flag:
  // one reporter at a time, so the host's callback is never called concurrently.
  RunContext quiet_ctx = operators_ctx;
  quiet_ctx.progress = nullptr;
  const bool beside = derived && requirements_checked(*derived, heat_requirements());
  ProgressTicker ticker(beside ? quiet_ctx : operators_ctx, "prepare heat method", 3.0);
  CscMatrix A;
  CscMatrix P;
  const EdgeIncidence* inc = derived ? &derived->incidence : nullptr;
  auto build_operators = [&] {
    const CancelScope scope(ticker);
    cancel_point_poll();
    prepare(m, derived);
    ticker.add(1.0);
    A = heat_operator(m, t_, inc);
    blend_mass(m, opt.mass_blend, A);
    normalize_heat_operator(A);
    ticker.add(1.0);
    P = poisson_operator(m, opt, inc);
  };
  // Both operators live on the same lower pattern: one ordering, one symbolic factor.
  // Every phase reports inside the caller's progress, weighted by its share of
  // this constructor's time at 416k vertices (docs/shipping.md): ordering,
  // analysis, then each factorization ~15%. One monotone fraction.
  auto order_and_analyze = [&](const CscMatrix& pattern) {
    const Ordering ord = order_matrix(pattern, {}, ctx.sub(kOrderBegin, kAnalyzeBegin));
    return analyze(pattern, ord, {}, ctx.sub(kAnalyzeBegin, kFactorBegin));
  };
  std::shared_ptr<const SymbolicFactor> S;
  if (beside) {
    // The mesh was checked and its edges are known: the ordering and symbolic
    // analysis (pattern only) run beside the checks and assembly of the values
    // (docs/ordering.md, "first answer").
    check_derived_of(*derived, m, "heat geodesic");
    const CscMatrix pattern = operator_pattern(m.num_vertices(), derived->incidence.edges);
    tbb::parallel_invoke([&] { S = order_and_analyze(pattern); }, build_operators);
  } else {
    build_operators();
    ctx.check_cancel();
    ctx.report(kOrderBegin, "prepare heat method");
    S = order_and_analyze(A);
  }
  factor_both(A, P, S, ctx);
}

void HeatGeodesic::factor_both(const CscMatrix& A, const CscMatrix& P, const std::shared_ptr<const SymbolicFactor>& S,
                               const RunContext& ctx) {
  ctx.check_cancel();
  {
    auto bytes = [](const auto& v) { return static_cast<double>(v.size() * sizeof(v[0])); };
    const double held = bytes(grad_.tri) + bytes(grad_.area) + bytes(grad_.basis) + bytes(grad_.vf_offsets) +
                        bytes(grad_.vf_faces) + bytes(vf_corners_) + bytes(component_) + bytes(A.values) +
                        bytes(A.rowind) + bytes(A.colptr) + bytes(P.values) + bytes(P.rowind) + bytes(P.colptr);
    check_memory(grad_.nv, held, *S, ctx);
  }
  // The two factorizations side by side: on small meshes one alone keeps two
  // threads only half busy (docs/ordering.md). The heat one reports for both;
  // the Poisson one only polls the cancel flag.
  RunContext poisson_ctx = ctx.sub(kPoissonBegin, 1.0);
  poisson_ctx.progress = nullptr;
  tbb::parallel_invoke([&] { heat_ = factorize(S, A, ctx.sub(kFactorBegin, 1.0)); },
                       [&] { poisson_ = factorize(S, P, poisson_ctx); });
  vertex_super_ = locus::vertex_supernodes(*S);
}

HeatGeodesic::HeatGeodesic(const Mesh& m, const RobustOperators& R, const HeatGeodesicOptions& opt,
                           const RunContext& ctx, const MeshDerived* derived)
    : opt_(opt) {
  if (R.L.ncols != m.num_vertices())
    fail(ErrorCode::BadUsage, "heat geodesic: the robust operators belong to another mesh");
  if (opt.mass_blend != 0.0)
    fail(ErrorCode::BadUsage, "heat geodesic: mass_blend applies to the cotan operator only");
  prepare(m, derived, &R);
  ctx.check_cancel();
  CscMatrix A = robust_heat_operator(R, t_);
  normalize_heat_operator(A);
  const CscMatrix P = robust_regularized_laplacian(R, opt.poisson_rel / std::max<int32_t>(1, m.num_vertices()));
  ctx.report(kOrderBegin, "prepare heat method");
  const Ordering ord = order_matrix(A, {}, ctx.sub(kOrderBegin, kAnalyzeBegin));
  const std::shared_ptr<const SymbolicFactor> S = analyze(A, ord, {}, ctx.sub(kAnalyzeBegin, kFactorBegin));
  factor_both(A, P, S, ctx);
}

HeatGeodesic::HeatGeodesic(const Mesh& m, const HeatGeodesicOptions& opt, HeatGeodesicFactors factors) : opt_(opt) {
  prepare(m);
  const CscMatrix A = heat_operator(m, t_);
  for (const NumericFactor* F : {&factors.heat, &factors.poisson})
    if (!F->symbolic || F->n() != m.num_vertices() || F->symbolic->a_pattern_hash != pattern_hash(A) ||
        !storage_matches_symbolic(*F))
      fail(ErrorCode::BadUsage, "heat geodesic: a given factor is not one of " + mesh_name(m) + "'s operators");
  heat_ = std::move(factors.heat);
  poisson_ = std::move(factors.poisson);
  // Plans are shared between the two solves only on one supernode structure.
  shared_symbolic_ = heat_.symbolic.get() == poisson_.symbolic.get() ||
                     (heat_.symbolic->perm == poisson_.symbolic->perm &&
                      heat_.symbolic->super_first_col == poisson_.symbolic->super_first_col);
  vertex_super_ = locus::vertex_supernodes(*heat_.symbolic);
}

namespace {

// Share of triangle area where the linear interpolant of the corner values r
// is <= cut (r = +inf allowed: that corner is beyond any cut).
double area_below(double r0, double r1, double r2, double cut) {
  double a = r0, b = r1, c = r2;
  if (a > b) std::swap(a, b);
  if (b > c) std::swap(b, c);
  if (a > b) std::swap(a, b);
  if (!(cut > a)) return 0.0;
  if (cut >= c) return 1.0;
  if (!std::isfinite(c)) return b <= cut ? 1.0 : 0.0;  // (underflowed corner: whole or nothing)
  if (cut <= b) return (cut - a) * (cut - a) / ((b - a) * (c - a));
  return 1.0 - (c - cut) * (c - cut) / ((c - a) * (c - b));
}

}  // namespace

// Output vertices k with h[k] below the smallest normal double. In the
// continuum rho = log(h_source / h) ~ d / sqrt(t), so t' = (dmax / 500)^2 keeps
// rho below 500 up to the largest distance dmax (subnormals begin at 708);
// where the mesh makes the heat decay faster than that (the largest slope
// rho / d among the others above 1 / sqrt(t)) t' grows by the same factor.
// (Far below h^2 the discrete heat falls like (t / h^2) per edge instead, a
// slope in log t, which no longer says anything about t'.)
void HeatGeodesic::note_underflow(std::span<const double> h, double h_source, std::span<const double> distance,
                                  HeatGeodesicWorkspace& ws) const {
  constexpr double kTiny = std::numeric_limits<double>::min();
  ws.underflow = 0;
  ws.t_no_underflow = 0;
  double slope = 0, dmax = 0;
  for (size_t k = 0; k < distance.size(); ++k) {
    if (!std::isfinite(distance[k])) continue;  // another component: no heat expected
    dmax = std::max(dmax, distance[k]);
    ws.underflow += !(h[k] >= kTiny);
  }
  if (ws.underflow == 0) return;
  for (size_t k = 0; k < distance.size(); ++k)  // the slope away from the source's neighborhood
    if (h[k] >= kTiny && distance[k] >= 0.25 * dmax && std::isfinite(distance[k]) && h_source > 0)
      slope = std::max(slope, (std::log(h_source) - std::log(h[k])) / distance[k]);  // (the ratio may overflow)
  const double faster = std::max(1.0, slope * slope * t_);
  ws.t_no_underflow = std::max(t_, (dmax / 500.0) * (dmax / 500.0) * faster);
}

// Rim (HeatGeodesicOptions::level_set_rim): the heat radius rho = -log h per
// region vertex (+inf where the heat underflowed) and its largest level cut
// whose sublevel set the patch contains (the ring's smallest rho); +inf when
// the region has no ring or the option is off.
double HeatGeodesic::rim_cut(const PatchRegion& r, std::span<const double> h, HeatGeodesicWorkspace& ws) const {
  const int32_t nloc = static_cast<int32_t>(r.verts.size()), np = r.patch_size;
  ws.rho.resize(static_cast<size_t>(nloc));
  double cut = std::numeric_limits<double>::infinity();
  for (int32_t k = 0; k < nloc; ++k) {
    ws.rho[k] = h[k] > 0 ? -ws.logh[k] : std::numeric_limits<double>::infinity();
    if (k >= np) cut = std::min(cut, ws.rho[k]);
  }
  return cut;
}

// The patch vertices beyond the cut, in increasing rho: each takes the value
// whose piecewise-linear gradient best fits the unit directions X of its faces
// whose other two corners are known (least squares, the Poisson step's own
// criterion, one vertex at a time); the few without such a face are retried
// once the others are known, and keep the Poisson value otherwise.
void HeatGeodesic::continue_rim(const PatchRegion& r, const double* hlb, double cut, HeatGeodesicWorkspace& ws) const {
  constexpr int kRec = 4;
  const int32_t nloc = static_cast<int32_t>(r.verts.size()), np = r.patch_size;
  HostVector<int32_t>& outer = ws.rim_order;
  outer.clear();
  for (int32_t k = 0; k < np; ++k)
    if (!(ws.rho[k] <= cut)) outer.push_back(k);
  if (outer.empty()) return;
  std::sort(outer.begin(), outer.end(), [&](int32_t a, int32_t b) { return ws.rho[a] < ws.rho[b] || (ws.rho[a] == ws.rho[b] && a < b); });
  // Faces per outer vertex (CSR over the outer list).
  HostVector<int32_t>& pos = ws.rim_pos;
  pos.assign(static_cast<size_t>(nloc), -1);
  for (size_t q = 0; q < outer.size(); ++q) pos[outer[q]] = static_cast<int32_t>(q);
  HostVector<int32_t>& off = ws.rim_offsets;
  off.assign(outer.size() + 1, 0);
  const size_t nfl = r.faces.size();
  for (size_t q = 0; q < 3 * nfl; ++q)
    if (pos[r.face_local[q]] >= 0) ++off[pos[r.face_local[q]] + 1];
  for (size_t q = 0; q < outer.size(); ++q) off[q + 1] += off[q];
  HostVector<int32_t>& fl = ws.rim_faces;
  fl.resize(static_cast<size_t>(off.back()));
  {
    HostVector<int32_t> fill(off.begin(), off.end() - 1);
    for (size_t q = 0; q < 3 * nfl; ++q)
      if (pos[r.face_local[q]] >= 0) fl[fill[pos[r.face_local[q]]]++] = static_cast<int32_t>(q);  // face slot 3f + s
  }
  HostVector<uint8_t>& known = ws.rim_known;
  known.assign(static_cast<size_t>(nloc), 0);
  for (int32_t k = 0; k < np; ++k) known[k] = ws.rho[k] <= cut;
  const bool lg = opt_.log_heat_gradient;
  auto solve_vertex = [&](size_t q) {
    double num = 0, den = 0;
    for (int32_t e = off[q]; e < off[q + 1]; ++e) {
      const int32_t slot = fl[e], qf = slot / 3, s = slot % 3;
      const int32_t* l = r.face_local.data() + 3 * static_cast<size_t>(qf);
      const int32_t a = l[(s + 1) % 3], b = l[(s + 2) % 3];
      if (!known[a] || !known[b]) continue;
      const int32_t f = r.faces[qf];
      const double lh[3] = {hlb[kRec * l[0] + 1], hlb[kRec * l[1] + 1], hlb[kRec * l[2] + 1]};
      double X[3];
      unit_direction(grad_, f, hlb[kRec * l[0]], hlb[kRec * l[1]], hlb[kRec * l[2]], lg ? lh : nullptr, X);
      if (X[0] == 0 && X[1] == 0 && X[2] == 0) continue;
      const double* bs = grad_.basis.data() + 9 * static_cast<int64_t>(f);
      const double* gv = bs + 3 * s;
      const double* ga = bs + 3 * ((s + 1) % 3);
      const double* gb = bs + 3 * ((s + 2) % 3);
      const double ua = ws.x[a], ub = ws.x[b], A = grad_.area[f];
      for (int c = 0; c < 3; ++c) {
        num += A * (X[c] - ua * ga[c] - ub * gb[c]) * gv[c];
        den += A * gv[c] * gv[c];
      }
    }
    if (!(den > 0)) return false;
    ws.x[outer[q]] = num / den;
    known[outer[q]] = 1;
    return true;
  };
  HostVector<int32_t>& later = ws.rim_later;
  later.clear();
  for (size_t q = 0; q < outer.size(); ++q)
    if (!solve_vertex(q)) later.push_back(static_cast<int32_t>(q));
  for (int round = 0; round < 4 && !later.empty(); ++round) {
    size_t keep = 0;
    for (int32_t q : later)
      if (!solve_vertex(static_cast<size_t>(q))) later[keep++] = q;
    if (keep == later.size()) break;
    later.resize(keep);
  }
}

void HeatGeodesic::distance_from_heat(const PatchRegion& r, std::span<const double> h, int32_t source_local,
                                      std::span<double> distance, HeatGeodesicWorkspace& ws,
                                      HeatGeodesicOptions::PoissonRhs rhs, const SolvePlan* heat_plan) const {
  const int32_t nloc = static_cast<int32_t>(r.verts.size()), np = r.patch_size;
  const bool flux = rhs == HeatGeodesicOptions::PoissonRhs::BoundaryFlux;
  const bool lg = opt_.log_heat_gradient;
  const bool level_cut = flux && opt_.level_set_rim;
  ws.logh.resize(static_cast<size_t>(nloc));
  if (lg || level_cut) log_array(h.data(), ws.logh.data(), static_cast<size_t>(nloc));  // NaN where h <= 0
  const double cut = level_cut ? rim_cut(r, h, ws) : std::numeric_limits<double>::infinity();
  const bool cutting = cut < std::numeric_limits<double>::infinity();
  // Per region vertex {h, log h, b} side by side: faces reach their corners in
  // no particular region order, and three separate arrays cost three cache
  // misses per corner (at 50 % of 416k the divergence was half gathers).
  constexpr int kRec = 4;
  ws.hlb.resize(static_cast<size_t>(kRec) * nloc);
  double* hlb = ws.hlb.data();
  for (int32_t k = 0; k < nloc; ++k) {
    hlb[kRec * k] = h[k];
    hlb[kRec * k + 1] = lg ? ws.logh[k] : 0.0;
    hlb[kRec * k + 2] = 0.0;
  }
  const size_t nfl = r.faces.size();
  for (size_t q = 0; q < nfl; ++q) {
    if (q + kAhead < nfl) {  // scattered faces: fetch their basis gradients, area and corner records ahead
      const int32_t fa = r.faces[q + kAhead];
      __builtin_prefetch(grad_.basis.data() + 9 * static_cast<int64_t>(fa));
      __builtin_prefetch(grad_.basis.data() + 9 * static_cast<int64_t>(fa) + 8);
      __builtin_prefetch(grad_.area.data() + fa);
      for (int s = 0; s < 3; ++s) __builtin_prefetch(hlb + kRec * r.face_local[3 * (q + kAhead) + s], 1);
    }
    const int32_t f = r.faces[q];
    const int32_t l[3] = {r.face_local[3 * q], r.face_local[3 * q + 1], r.face_local[3 * q + 2]};
    double* c0 = hlb + kRec * l[0];
    double* c1 = hlb + kRec * l[1];
    double* c2 = hlb + kRec * l[2];
    double X[3], d[3];
    const double lh[3] = {c0[1], c1[1], c2[1]};
    // Level-set rim: only the part of the face inside rho <= cut carries X.
    const double share = cutting ? area_below(ws.rho[l[0]], ws.rho[l[1]], ws.rho[l[2]], cut) : 1.0;
    if (share == 0.0) continue;
    unit_direction(grad_, f, c0[0], c1[0], c2[0], lg ? lh : nullptr, X);
    corner_divergence(grad_, f, X, d);
    double* c[3] = {c0, c1, c2};
    for (int s = 0; s < 3; ++s)
      if (flux || l[s] < np) c[s][2] += share * d[s];
  }
  ws.b.resize(static_cast<size_t>(flux ? nloc : np));
  for (size_t k = 0; k < ws.b.size(); ++k) ws.b[k] = hlb[kRec * k + 2];
  const double t0 = thread_cpu_seconds();
  const std::span<const int32_t> support(r.verts.data(), ws.b.size());
  const std::span<const int32_t> wanted(r.verts.data(), static_cast<size_t>(np));
  if (heat_plan && shared_symbolic_)
    plan_subset_solve_within(*poisson_.symbolic, *heat_plan, support, wanted, ws.poisson_plan, ws.plan_ws);
  else
    plan_subset_solve(*poisson_.symbolic, shared_symbolic_ ? std::span<const int32_t>(vertex_super_) : std::span<const int32_t>(),
                      support, wanted, ws.poisson_plan, ws.plan_ws);
  ws.x.resize(static_cast<size_t>(np));
  solve_planned(poisson_, ws.poisson_plan, ws.b, ws.x, ws.poisson);
  ws.poisson_s = thread_cpu_seconds() - t0;
  if (cutting) continue_rim(r, hlb, cut, ws);
  const double d0 = ws.x[source_local];
  const int32_t c = component_[r.verts[source_local]];
  for (int32_t k = 0; k < np; ++k)
    distance[k] = component_[r.verts[k]] == c ? ws.x[k] - d0 : std::numeric_limits<double>::infinity();
  // (PoissonRhs::Truncated, a measured alternative, bends d inside P by design: not checked.)
  if (flux)
    check_distances(distance.first(static_cast<size_t>(np)),
                    std::span<const int32_t>(r.verts.data(), static_cast<size_t>(np)), opt_.t_factor,
                    dip_tolerance(), ws.dips, ws.deepest_dip);
  note_underflow(h.first(static_cast<size_t>(np)), h[source_local], distance, ws);
}

void HeatGeodesic::distance_from_heat_full(std::span<const double> h, int32_t source, std::span<double> distance,
                                           HeatGeodesicWorkspace& ws) const {
  potential_from_heat_full(h, ws);
  const int32_t n = grad_.nv;
  const double d0 = ws.b[source];
  const int32_t c = component_[source];
  for (int32_t i = 0; i < n; ++i)
    distance[i] = component_[i] == c ? ws.b[i] - d0 : std::numeric_limits<double>::infinity();
  check_distances(distance, {}, opt_.t_factor, dip_tolerance(), ws.dips, ws.deepest_dip);
  note_underflow(h, h[source], distance, ws);
}

void HeatGeodesic::potential_from_heat_full(std::span<const double> h, HeatGeodesicWorkspace& ws) const {
  const int32_t n = grad_.nv;
  ws.b.assign(static_cast<size_t>(n), 0.0);
  const bool lg = opt_.log_heat_gradient;
  if (lg) {
    ws.logh.resize(static_cast<size_t>(n));
    log_array(h.data(), ws.logh.data(), static_cast<size_t>(n));  // NaN where h <= 0
  }
  for (int32_t f = 0; f < grad_.nf; ++f) {
    const int32_t* t = grad_.tri.data() + 3 * static_cast<int64_t>(f);
    double X[3], d[3];
    const double lh[3] = {lg ? ws.logh[t[0]] : 0.0, lg ? ws.logh[t[1]] : 0.0, lg ? ws.logh[t[2]] : 0.0};
    unit_direction(grad_, f, h[t[0]], h[t[1]], h[t[2]], lg ? lh : nullptr, X);
    corner_divergence(grad_, f, X, d);
    for (int s = 0; s < 3; ++s) ws.b[t[s]] += d[s];
  }
  ws.x.resize(solve_work_size(poisson_, 1));
  solve(poisson_, ws.b, ws.x);
}

void HeatGeodesic::query(int32_t source, std::span<const int32_t> patch, std::span<double> distance,
                         HeatGeodesicWorkspace& ws, HeatGeodesicOptions::PoissonRhs rhs) const {
  check_vertex(source, grad_.nv, "source");
  if (distance.size() != patch.size())
    fail(ErrorCode::BadUsage, "heat geodesic: distance has " + std::to_string(distance.size()) +
                                  " entries for a patch of " + std::to_string(patch.size()));
  PatchRegion& r = ws.region;
  build_region(patch, r);
  const int32_t sl = r.local[source];
  if (sl < 0 || sl >= r.patch_size) {
    release_region(r);
    fail(ErrorCode::BadUsage, "the source vertex " + std::to_string(source) + " is not in the patch");
  }
  try {
    const int32_t src[1] = {source};
    const double one[1] = {1.0};
    plan_subset_solve(*heat_.symbolic, vertex_super_, src, r.verts, ws.heat_plan, ws.plan_ws);
    ws.h.resize(r.verts.size());
    solve_planned(heat_, ws.heat_plan, one, ws.h, ws.heat);
    distance_from_heat(r, ws.h, sl, distance, ws, rhs, &ws.heat_plan);
  } catch (...) {
    release_region(r);
    throw;
  }
  release_region(r);
}

void HeatGeodesic::query_full(int32_t source, std::span<double> distance, HeatGeodesicWorkspace& ws) const {
  const int32_t n = grad_.nv;
  check_vertex(source, n, "source");
  if (distance.size() != static_cast<size_t>(n))
    fail(ErrorCode::BadUsage, "heat geodesic: distance has " + std::to_string(distance.size()) + " entries for " +
                                  std::to_string(n) + " vertices");
  HostVector<double>& h = ws.h;
  h.assign(static_cast<size_t>(n), 0.0);
  h[source] = 1.0;
  ws.x.resize(solve_work_size(heat_, 1));
  solve(heat_, h, ws.x);
  // distance_from_heat_full reuses ws.b and ws.x, not ws.h.
  distance_from_heat_full(h, source, distance, ws);
}

}  // namespace locus
