// Dijkstra balls and graph-geodesic cells of sites
// (pipelines/include/locus/pipelines/voronoi/site_neighborhoods.hpp; thesis §3.6).
#include "locus/pipelines/voronoi/site_neighborhoods.hpp"
#include "locus/core/host_allocator.hpp"
#include "locus/kernels/mesh/nearest_seed_buckets.hpp"

#include <oneapi/tbb/enumerable_thread_specific.h>
#include <oneapi/tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace locus {

namespace {

// Vertices within graph distance `radius` of a surface point, sorted: the patch
// grower's geodesic ball from the corners of the point's support.
std::vector<int32_t> geodesic_ball(const Mesh& m, const Adjacency& adj, const SurfacePoint& s, double radius,
                                   GrowWorkspace& w) {
  GrowSeed seeds[3];
  const int cnt = site_seeds(m, s, seeds);
  GrowOptions o;
  o.mode = GrowMode::Geodesic;
  o.max_radius = radius;
  o.radius_rule = RadiusRule::PruneBeyond;
  HostVector<int32_t> out;
  grow_geodesic_vertices(adj, m, std::span<const GrowSeed>(seeds, static_cast<size_t>(cnt)), o, w, out);
  std::sort(out.begin(), out.end());
  return std::vector<int32_t>(out);
}

}  // namespace

int site_seeds(const Mesh& m, const SurfacePoint& s, GrowSeed seeds[3]) {
  const auto p = surface_point_position(m, s);
  int32_t sv[3];
  double sw[3];
  const int cnt = surface_point_support(m, s, sv, sw);
  for (int k = 0; k < cnt; ++k)
    seeds[k] = {sv[k], std::sqrt((m.x[sv[k]] - p[0]) * (m.x[sv[k]] - p[0]) + (m.y[sv[k]] - p[1]) * (m.y[sv[k]] - p[1]) +
                                 (m.z[sv[k]] - p[2]) * (m.z[sv[k]] - p[2]))};
  return cnt;
}

std::vector<std::vector<int32_t>> geodesic_neighborhoods(const Mesh& m, const Adjacency& adj,
                                                         std::span<const SurfacePoint> sites, double radius,
                                                         const RunContext& ctx) {
  const int32_t ns = static_cast<int32_t>(sites.size());
  std::vector<std::vector<int32_t>> nb(ns);
  // Edge lengths as the balls reach them: no mesh-wide array (20 MB at 416k
  // vertices, held beside the repair's factor for a few relabelled sites).
  tbb::enumerable_thread_specific<GrowWorkspace> scratch;
  tbb::parallel_for(0, ns, [&](int32_t s) {
    if (!ctx.cancelled()) nb[s] = geodesic_ball(m, adj, sites[s], radius, scratch.local());
  });
  ctx.check_cancel();
  return nb;
}

HostVector<int32_t> geodesic_site_cells(const Mesh& m, const Adjacency& adj, std::span<const SurfacePoint> sites) {
  std::vector<GrowSeed> seeds;
  std::vector<int32_t> seed_site;
  for (int32_t s = 0; s < static_cast<int32_t>(sites.size()); ++s) {
    GrowSeed g[3];
    const int cnt = site_seeds(m, sites[s], g);
    seeds.insert(seeds.end(), g, g + cnt);
    seed_site.insert(seed_site.end(), static_cast<size_t>(cnt), s);
  }
  HostVector<int32_t> label(static_cast<size_t>(m.num_vertices()));
  const SeedBucketPlan plan = prepare_seed_buckets(adj, m);
  if (plan.usable()) {
    SeedBucketWorkspace ws;
    label_nearest_seeds_bucketed(adj, m, plan, seeds, seed_site, ws, label);
  } else {
    GrowWorkspace ws;
    label_nearest_seeds_by_positions(adj, m, seeds, seed_site, ws, label);
  }
  return label;
}

HostVector<int32_t> geodesic_lloyd(const Mesh& m, const Adjacency& adj, std::span<const double> mass,
                                   std::vector<SurfacePoint>& sites, int iterations, const RunContext& ctx) {
  const int32_t n = m.num_vertices();
  const int32_t ns = static_cast<int32_t>(sites.size());
  // Edge lengths as the labellings reach them: no mesh-wide array beside
  // Lloyd's setup. A bucket queue where the edges' lengths allow it (the
  // heap's labels but for exact ties, ~2x faster: docs/cvt.md).
  const SeedBucketPlan plan = prepare_seed_buckets(adj, m);
  SeedBucketWorkspace bws;
  GrowWorkspace ws;
  HostVector<int32_t> label(static_cast<size_t>(n));
  std::vector<GrowSeed> seeds;
  std::vector<int32_t> seed_site;
  auto cells = [&] {
    seeds.clear();
    seed_site.clear();
    for (int32_t s = 0; s < ns; ++s) {
      GrowSeed g[3];
      const int cnt = site_seeds(m, sites[s], g);
      seeds.insert(seeds.end(), g, g + cnt);
      seed_site.insert(seed_site.end(), static_cast<size_t>(cnt), s);
    }
    if (plan.usable())
      label_nearest_seeds_bucketed(adj, m, plan, seeds, seed_site, bws, label);
    else
      label_nearest_seeds_by_positions(adj, m, seeds, seed_site, ws, label);
  };
  std::vector<double> sum(4 * static_cast<size_t>(ns));
  std::vector<double> best(ns);
  std::vector<int32_t> arg(ns);
  for (int it = 0; it < iterations; ++it) {
    ctx.check_cancel();
    cells();
    std::fill(sum.begin(), sum.end(), 0.0);
    for (int32_t v = 0; v < n; ++v) {  // vertex order: deterministic sums
      const int32_t s = label[v];
      if (s < 0) continue;
      double* a = sum.data() + 4 * static_cast<size_t>(s);
      a[0] += mass[v] * m.x[v];
      a[1] += mass[v] * m.y[v];
      a[2] += mass[v] * m.z[v];
      a[3] += mass[v];
    }
    std::fill(best.begin(), best.end(), std::numeric_limits<double>::infinity());
    std::fill(arg.begin(), arg.end(), -1);
    for (int32_t v = 0; v < n; ++v) {  // the cell's vertex nearest its mean (smallest id on ties)
      const int32_t s = label[v];
      if (s < 0 || !(sum[4 * static_cast<size_t>(s) + 3] > 0)) continue;
      const double* a = sum.data() + 4 * static_cast<size_t>(s);
      const double dx = m.x[v] - a[0] / a[3], dy = m.y[v] - a[1] / a[3], dz = m.z[v] - a[2] / a[3];
      const double d = dx * dx + dy * dy + dz * dz;
      if (d < best[s]) {
        best[s] = d;
        arg[s] = v;
      }
    }
    for (int32_t s = 0; s < ns; ++s)
      if (arg[s] >= 0) sites[s] = vertex_point(arg[s]);
  }
  cells();
  return label;
}

}  // namespace locus
