// The heat log map's two queries (pipelines/include/locus/pipelines/geodesic/logmap.hpp;
// thesis §6.5-6.6): the localized one (exact subset solves over the patch's
// region, all sources in one wide pass when they fit) and the full one
// (whole-mesh solves, the thesis' baseline). Both check the query, choose the
// estimator for the center (logmap_estimator.cpp), solve the heat from every
// source, estimate one gradient per patch vertex and the distance from the
// center's heat, then share one tail (finish_query). Measurements behind the
// localized query's layout: docs/logmap.md, "Kernel tuning".
#include <algorithm>
#include <cstdint>
#include <limits>
#include <string>

#include "locus/error.hpp"
#include "locus/kernels/parallel/thread_cpu_time.hpp"
#include "locus/kernels/solve/solve_full.hpp"
#include "locus/kernels/solve/solve_plan.hpp"
#include "locus/kernels/solve/solve_wide.hpp"
#include "locus/pipelines/geodesic/logmap.hpp"

namespace locus {

namespace {

void check_center_vertex(int32_t center, int32_t n) {
  if (center < 0 || center >= n)
    fail(ErrorCode::BadUsage, "center " + std::to_string(center) + " is not a vertex (the mesh has " +
                                  std::to_string(n) + " vertices)");
}

void check_outputs(const LogMapOutput& out, size_t np) {
  if (out.distance.size() != np || out.angle.size() != np || out.u.size() != np || out.v.size() != np)
    fail(ErrorCode::BadUsage, "log map: every output span needs one entry per patch vertex (" + std::to_string(np) + ")");
}

// A vertex in another component than the center has no geodesic path to it
// and receives no heat from it: no distance, no direction. Refused rather than
// mapped to infinity or NaN. Patch ids are already checked to be in range.
void check_same_component(const HeatGeodesic& geo, int32_t center, std::span<const int32_t> patch) {
  if (geo.num_components() <= 1) return;
  const int32_t c = geo.component(center);
  for (size_t k = 0; k < patch.size(); ++k)
    if (geo.component(patch[k]) != c)
      fail(ErrorCode::BadUsage, "log map: patch entry " + std::to_string(k) + " is vertex " + std::to_string(patch[k]) +
                                    ", in another connected component than the center " + std::to_string(center));
}

// Thread CPU time per phase of a query (LogMapStats): lap(phase) stores the
// time since the previous lap.
struct PhaseClock {
  double tick = thread_cpu_seconds();
  void lap(double& phase) {
    const double now = thread_cpu_seconds();
    phase = now - tick;
    tick = now;
  }
};

}  // namespace

// The head both queries share once the patch is known to hold the center: the
// estimator for this center and the sources' statistics.
LogMapEstimator HeatLogMap::begin_query(int32_t center, std::span<const int32_t> patch,
                                        const LogMapEstimator& estimator, int32_t region_size, LogMapStats& st,
                                        LogMapWorkspace& ws) const {
  check_same_component(geo_, center, patch);
  const LogMapEstimator est = prepare_center(center, estimator, ws);
  const int32_t d = static_cast<int32_t>(ws.estimator.sources.size());
  st.two_ring = !ws.estimator.coef2.empty();
  st.sources = d;
  st.batches = (d + kLanes - 1) / kLanes;
  st.region_size = region_size;
  return est;
}

// All sources in one pass over the plan's supernodes (kernels/include/locus/kernels/solve/solve_wide.hpp),
// W lanes (|S| rounded up to a multiple of 8): the results stay in ws.heat.wide's rows.
void HeatLogMap::solve_heat_one_pass(int32_t W, LogMapWorkspace& ws) const {
  LogMapHeatWorkspace& hw = ws.heat;
  const int32_t d = static_cast<int32_t>(ws.estimator.sources.size());
  hw.rhs.assign(static_cast<size_t>(d) * W, 0.0);
  for (int32_t l = 0; l < d; ++l) hw.rhs[static_cast<size_t>(l) * W + l] = 1.0;
  solve_planned_wide(geo_.heat_factor(), ws.plan, W, hw.rhs, {}, hw.wide);
}

// After solve_heat_one_pass: the solver's rows are read once, in memory order,
// instead of gathered into region order first (see docs/logmap.md, "Kernel
// tuning"): each row gives the center's heat (lane 0, into ws.geo.h) for the
// distance and, at patch vertices, the gradient estimate.
void HeatLogMap::gradients_from_rows(int32_t W, int32_t center_local, const LogMapEstimator& est, LogMapStats& st,
                                     LogMapWorkspace& ws) const {
  const PatchRegion& r = ws.geo.region;
  LogMapHeatWorkspace& hw = ws.heat;
  const size_t nloc = r.verts.size();
  const int32_t np = r.patch_size;
  const HostVector<int32_t>& rows = hw.wide.out_rows;
  const double* X = hw.wide.x.data();
  const size_t xrows = hw.wide.x.size() / static_cast<size_t>(W);
  // Owner of each row: its region index, with kSourceBit set for the
  // sources (no lookups by vertex id inside the loop: those were cache misses).
  constexpr int32_t kSourceBit = 1 << 30;
  hw.row_owner.assign(xrows, -1);
  for (size_t k = 0; k < nloc; ++k) hw.row_owner[rows[k]] = static_cast<int32_t>(k);
  for (int32_t v : ws.estimator.sources)  // (the two-ring may reach beyond a tiny patch's region)
    if (r.local[v] >= 0) hw.row_owner[rows[r.local[v]]] |= kSourceBit;
  const double h_center = X[static_cast<size_t>(rows[center_local]) * W];
  for (size_t row = 0; row < xrows; ++row) {
    const int32_t o = hw.row_owner[row];
    if (o < 0) continue;
    const int32_t k = o & (kSourceBit - 1);
    const double* f = X + row * static_cast<size_t>(W);
    ws.geo.h[k] = f[0];
    if (k < np)
      vertex_gradient(static_cast<size_t>(k), k == center_local, (o & kSourceBit) != 0, f, true, h_center, est, st,
                      ws.estimator, ws.path);
  }
}

// More than kMaxWideLanes sources (valence > 31): `passes` wide solves of W
// lanes, gathered into ws.heat.table (region order, W * passes values per vertex).
void HeatLogMap::solve_heat_passes(int32_t W, int32_t passes, LogMapWorkspace& ws) const {
  LogMapHeatWorkspace& hw = ws.heat;
  const int32_t d = static_cast<int32_t>(ws.estimator.sources.size());
  const size_t nloc = ws.geo.region.verts.size();
  hw.table.resize(nloc * static_cast<size_t>(W) * passes);
  const int64_t stride = static_cast<int64_t>(W) * passes;
  for (int32_t ps = 0; ps < passes; ++ps) {
    const int32_t k0 = ps * W, lanes = std::min(W, d - k0);
    hw.rhs.assign(static_cast<size_t>(d) * W, 0.0);
    for (int32_t l = 0; l < lanes; ++l) hw.rhs[static_cast<size_t>(k0 + l) * W + l] = 1.0;
    hw.out.resize(nloc * static_cast<size_t>(W));
    solve_planned_wide(geo_.heat_factor(), ws.plan, W, hw.rhs, hw.out, hw.wide);
    for (size_t v = 0; v < nloc; ++v)
      std::copy_n(hw.out.begin() + static_cast<int64_t>(v) * W, W, hw.table.begin() + static_cast<int64_t>(v) * stride + k0);
  }
}

// The full query's heat from every source at every vertex, in 8-lane
// batches of whole-mesh solves: ws.heat.table, one row of |S| per vertex.
void HeatLogMap::solve_heat_full(int32_t batches, LogMapWorkspace& ws) const {
  LogMapHeatWorkspace& hw = ws.heat;
  const HostVector<int32_t>& S = ws.estimator.sources;
  const int32_t n = num_vertices(), d = static_cast<int32_t>(S.size());
  const NumericFactor& F = geo_.heat_factor();
  hw.table.resize(static_cast<size_t>(n) * d);
  hw.out8.resize(static_cast<size_t>(n) * kLanes);
  hw.work.resize(solve_work_size(F, kLanes));
  for (int32_t bt = 0; bt < batches; ++bt) {
    std::fill(hw.out8.begin(), hw.out8.end(), 0.0);
    const int32_t k0 = bt * kLanes, lanes = std::min(kLanes, d - k0);
    for (int32_t l = 0; l < lanes; ++l) hw.out8[static_cast<size_t>(S[k0 + l]) * kLanes + l] = 1.0;
    solve8(F, hw.out8, hw.work);
    for (int32_t v = 0; v < n; ++v)
      for (int32_t l = 0; l < lanes; ++l)
        hw.table[static_cast<size_t>(v) * d + k0 + l] = hw.out8[static_cast<size_t>(v) * kLanes + l];
  }
}

// The gradient estimate of every patch vertex from ws.heat.table, whose rows
// (`stride` values apart, value k the heat from source k) belong to patch
// positions (row_of empty: the localized passes, patch index = region index)
// or to vertex ids (row_of = the patch: the full solves).
void HeatLogMap::gradients_from_table(std::span<const int32_t> patch, int32_t center, std::span<const int32_t> row_of,
                                      size_t center_row, size_t stride, const LogMapEstimator& est, LogMapStats& st,
                                      LogMapWorkspace& ws) const {
  const LogMapEstimatorWorkspace& ew = ws.estimator;
  const double* table = ws.heat.table.data();
  const double h_center = table[center_row * stride];
  for (size_t p = 0; p < patch.size(); ++p) {
    const size_t row = row_of.empty() ? p : static_cast<size_t>(row_of[p]);
    vertex_gradient(p, patch[p] == center,
                    std::binary_search(ew.sorted_sources.begin(), ew.sorted_sources.end(), patch[p]),
                    table + row * stride, false, h_center, est, st, ws.estimator, ws.path);
  }
}

// The tail both queries share, after every gradient and the distances: the
// corrections, the angles and (u, v).
void HeatLogMap::finish_query(std::span<const int32_t> patch, const LogMapOutput& out, const LogMapEstimator& est,
                              LogMapStats& st, LogMapWorkspace& ws) const {
  finish_angles(patch, out, est, st, ws);
  scale_by_distance(out);
}

LogMapStats HeatLogMap::query(int32_t center, std::span<const int32_t> patch, const LogMapOutput& out,
                              LogMapWorkspace& ws, const LogMapEstimator& estimator) const {
  check_center_vertex(center, num_vertices());
  check_outputs(out, patch.size());
  PhaseClock clock;
  PatchRegion& r = ws.geo.region;
  geo_.build_region(patch, r);
  LogMapStats st;
  clock.lap(st.region_s);
  try {
    const int32_t cl = r.local[center];
    if (cl < 0 || cl >= r.patch_size)
      fail(ErrorCode::BadUsage, "the center vertex " + std::to_string(center) + " is not in the patch");
    const size_t nloc = r.verts.size();
    const LogMapEstimator est = begin_query(center, patch, estimator, static_cast<int32_t>(nloc), st, ws);
    clock.lap(st.center_s);
    plan_subset_solve(*geo_.heat_factor().symbolic, geo_.vertex_supernodes(), ws.estimator.sources, r.verts, ws.plan,
                      ws.plan_ws);
    clock.lap(st.plan_s);
    // Lanes rounded up to a multiple of 8; more than kMaxWideLanes sources
    // (valence > 31) take further passes into the same rows.
    const int32_t d = st.sources;
    const int32_t W = std::min(kMaxWideLanes, (d + kLanes - 1) / kLanes * kLanes);
    st.passes = (d + W - 1) / W;
    ws.geo.h.resize(nloc);
    begin_gradients(patch.size(), ws.estimator, ws.path);
    if (st.passes == 1) {
      solve_heat_one_pass(W, ws);
      clock.lap(st.heat_s);
      gradients_from_rows(W, cl, est, st, ws);
    } else {
      solve_heat_passes(W, st.passes, ws);
      clock.lap(st.heat_s);
      const size_t stride = static_cast<size_t>(W) * st.passes;
      for (size_t v = 0; v < nloc; ++v) ws.geo.h[v] = ws.heat.table[v * stride];
      gradients_from_table(patch, center, {}, static_cast<size_t>(cl), stride, est, st, ws);
    }
    double t_gradients = 0;
    clock.lap(t_gradients);
    // Distance from lane 0 (the heat from the center).
    geo_.distance_from_heat(r, ws.geo.h, cl, out.distance, ws.geo, opt_.geodesic.poisson_rhs, &ws.plan);
    clock.lap(st.distance_s);
    st.poisson_s = ws.geo.poisson_s;
    st.underflow = ws.geo.underflow;
    st.t_no_underflow = ws.geo.t_no_underflow;
    finish_query(patch, out, est, st, ws);
    st.angles_s = t_gradients;
  } catch (...) {
    geo_.release_region(r);
    throw;
  }
  geo_.release_region(r);
  double t_finish = 0;
  clock.lap(t_finish);  // (finish_query, with the region's release)
  st.angles_s += t_finish;
  return st;
}

LogMapStats HeatLogMap::query_full(int32_t center, std::span<const int32_t> patch, const LogMapOutput& out,
                                   LogMapWorkspace& ws, const LogMapEstimator& estimator) const {
  const int32_t n = num_vertices();
  check_center_vertex(center, n);
  check_outputs(out, patch.size());
  bool has_center = false;
  for (int32_t v : patch) {
    if (v < 0 || v >= n) fail(ErrorCode::BadUsage, "patch vertex " + std::to_string(v) + " is out of range");
    has_center |= v == center;
  }
  if (!has_center) fail(ErrorCode::BadUsage, "the center vertex " + std::to_string(center) + " is not in the patch");
  LogMapStats st;
  const LogMapEstimator est = begin_query(center, patch, estimator, n, st, ws);
  const int32_t d = st.sources;
  solve_heat_full(st.batches, ws);
  LogMapHeatWorkspace& hw = ws.heat;
  HostVector<double>& h0 = ws.geo.h;
  h0.resize(static_cast<size_t>(n));
  for (int32_t v = 0; v < n; ++v) h0[v] = hw.table[static_cast<size_t>(v) * d];
  hw.distance.resize(static_cast<size_t>(n));
  geo_.distance_from_heat_full(h0, center, hw.distance, ws.geo);
  for (size_t p = 0; p < patch.size(); ++p) out.distance[p] = hw.distance[patch[p]];
  st.underflow = 0;  // (the whole-mesh count above is not the patch's)
  for (int32_t v : patch)
    if (!(h0[v] >= std::numeric_limits<double>::min())) ++st.underflow;
  st.t_no_underflow = st.underflow > 0 ? ws.geo.t_no_underflow : 0.0;
  begin_gradients(patch.size(), ws.estimator, ws.path);
  gradients_from_table(patch, center, patch, static_cast<size_t>(center), static_cast<size_t>(d), est, st, ws);
  finish_query(patch, out, est, st, ws);
  return st;
}

}  // namespace locus
