// CVT remeshing: Lloyd, restricted dual, repair by added sites
// (pipelines/include/locus/pipelines/voronoi/cvt_remesh.hpp; thesis §3.7.1).
#include "locus/pipelines/voronoi/cvt_remesh.hpp"

#include <oneapi/tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>
#include <utility>

#include "locus/error.hpp"
#include "locus/kernels/heat/heat_diffusion.hpp"
#include "locus/kernels/parallel/stopwatch.hpp"
#include "locus/kernels/parallel/task_arenas.hpp"
#include "locus/pipelines/voronoi/remesh_quality.hpp"
#include "locus/pipelines/voronoi/triangle_grid.hpp"

namespace locus {

namespace {

// One repair round without relaxation: the sites beyond r's are new; only they
// are solved (on Dijkstra balls of 2.5 expected cell radii, as the relaxing
// rounds' first neighborhoods) and merged into r's diagram.
void add_sites(const Mesh& m, const MeshDerived& d, const HeatDiffusion& H, std::vector<SurfacePoint> sites,
               const RunContext& ctx, LloydResult& r) {
  const int32_t first = static_cast<int32_t>(r.sites.size());
  const int32_t ns = static_cast<int32_t>(sites.size());
  const double area = std::accumulate(d.mass.begin(), d.mass.end(), 0.0);
  const double radius = 2.5 * std::sqrt(area / (M_PI * ns));
  const std::span<const SurfacePoint> fresh(sites.data() + first, static_cast<size_t>(ns - first));
  const int threads = ctx.threads > 0 ? ctx.threads : tbb::this_task_arena::max_concurrency();
  std::vector<std::vector<int32_t>> nb;
  run_with_threads(std::max(1, threads), [&] { nb = geodesic_neighborhoods(m, d.adjacency, fresh, radius, ctx); });
  heat_voronoi_add(H, m, sites, first, nb, {}, r.voronoi, ctx);
  r.sites = std::move(sites);
  r.label.assign(r.voronoi.label.begin(), r.voronoi.label.end());
}

}  // namespace

RemeshResult cvt_remesh(const Mesh& m, const MeshDerived& d, const RemeshOptions& o, const RunContext& ctx) {
  if (o.max_repair_rounds < 0 || o.relax_iterations < 0)
    fail(ErrorCode::BadUsage, "cvt remesh: repair rounds and relaxation iterations must be >= 0");
  RemeshResult r;
  BatchStopwatch sw;
  LloydOptions lo = o.lloyd;
  // One factor for every round (isotropic cells; the lifted metric is factored per run).
  HeatDiffusion own;
  double lloyd_begin = 0.0;  // after the factorization's share of the progress, when it runs here
  if (!lo.prepared && lo.anisotropy == 0) {
    lloyd_begin = 0.3;
    own = prepare_heat_diffusion(m, d, lo.t_factor, lo.t_abs, ctx.sub(0.0, lloyd_begin));
    lo.prepared = &own;
    r.factor_s = sw.lap();
  }
  // One monotone progress fraction: the Lloyd iterations, then each repair
  // round's share, then the dual and its optimization.
  constexpr double kLloydEnd = 0.7, kRepairEnd = 0.9;
  // Repair rounds without relaxation only add sites: they grow the final
  // diagram (heat_voronoi_add) instead of relabelling from scratch.
  const bool incremental = o.relax_iterations == 0 && lo.prepared && lo.solver == LloydOptions::Solver::Local;
  lo.keep_voronoi = incremental;
  r.lloyd = cvt_lloyd(m, d, lo, ctx.sub(lloyd_begin, kLloydEnd));
  r.lloyd_iterations = static_cast<int32_t>(r.lloyd.iter_s.size());
  r.lloyd_s = sw.lap();
  const DualTopology topo = dual_topology(m);
  RestrictedDual dual = restricted_dual(m, topo, r.lloyd.label, r.lloyd.sites);
  r.first_defects = dual.defects;
  r.dual_s += sw.lap();
  for (int round = 0; round < o.max_repair_rounds && dual.defects.total() > 0; ++round) {
    ctx.check_cancel();
    std::vector<SurfacePoint> sites = r.lloyd.sites;
    for (int32_t v : dual.repair_vertices) sites.push_back(vertex_point(v));
    r.added_sites += static_cast<int32_t>(dual.repair_vertices.size());
    if (incremental) {
      const double share = (kRepairEnd - kLloydEnd) / std::max(1, o.max_repair_rounds);
      add_sites(m, d, *lo.prepared, std::move(sites), ctx.sub(kLloydEnd + round * share, kLloydEnd + (round + 1) * share),
                r.lloyd);
      ++r.repair_rounds;
      r.repair_s += sw.lap();
      dual = restricted_dual(m, topo, r.lloyd.label, r.lloyd.sites);
      r.dual_s += sw.lap();
      continue;
    }
    LloydOptions ro = lo;
    // The last rounds only relabel: relaxation could open new defects elsewhere.
    ro.iterations = round + 2 < o.max_repair_rounds ? o.relax_iterations : 0;
    // The sites are spread already: first neighborhoods of 2.5 expected cell
    // radii (not 4) hold every cell and its neighbors (1.5 left vertices
    // unreached on armadillo at 5,000 sites).
    ro.init_radius = std::min(lo.init_radius, 2.5);
    const double share = (kRepairEnd - kLloydEnd) / std::max(1, o.max_repair_rounds);
    r.lloyd = cvt_lloyd(m, d, std::move(sites), ro, ctx.sub(kLloydEnd + round * share, kLloydEnd + (round + 1) * share));
    r.lloyd_iterations += static_cast<int32_t>(r.lloyd.iter_s.size());
    ++r.repair_rounds;
    r.repair_s += sw.lap();
    dual = restricted_dual(m, topo, r.lloyd.label, r.lloyd.sites);
    r.dual_s += sw.lap();
  }
  ctx.check_cancel();
  ctx.report(kRepairEnd, "remesh");
  r.defects = dual.defects;
  r.complete = dual.defects.total() == 0;
  if (r.complete) r.remesh = dual_mesh(m, dual, r.lloyd.sites, r.vertex_site);
  r.dual_s += sw.lap();
  if (r.complete) {
    const RemeshStats raw = remesh_stats(m, r.remesh, false);
    r.dual_mean_min_angle_deg = raw.mean_min_angle_deg;
    r.dual_min_angle_deg = raw.min_angle_deg;
    if (o.optimize_rounds > 0) {
      const TriangleGrid grid(m);
      RemeshOptimizeOptions oo;
      oo.rounds = o.optimize_rounds;
      r.optimize = optimize_remesh(m, grid, r.remesh, oo);
    }
    r.optimize_s = sw.lap();
  }
  ctx.report(1.0, "remesh");
  return r;
}

}  // namespace locus
