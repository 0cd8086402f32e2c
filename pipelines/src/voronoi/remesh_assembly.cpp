// The remesh from a manifold restricted dual
// (pipelines/src/voronoi/remesh_assembly.hpp; thesis §3.7.1).
#include "remesh_assembly.hpp"

#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

#include "locus/pipelines/voronoi/remesh_collapse.hpp"
#include "locus/pipelines/voronoi/remesh_features.hpp"
#include "locus/pipelines/voronoi/remesh_fidelity.hpp"
#include "locus/pipelines/voronoi/remesh_quality.hpp"
#include "locus/pipelines/voronoi/remesh_rebalance.hpp"
#include "locus/pipelines/voronoi/remesh_small_components.hpp"
#include "locus/pipelines/voronoi/remesh_split.hpp"
#include "locus/pipelines/voronoi/triangle_grid.hpp"

namespace locus {

namespace {

// Triangles below 25 degrees left by the optimization (a fan towards a
// boundary loop far shorter than the edges): their longest edges split, up to
// 1.5% above the request, and two optimization rounds; kept when the smallest
// angle grew (remesh_split.hpp; ChineseDragon-10kv 20.9 -> 27.6 degrees).
void split_and_reoptimize(const Mesh& m, const TriangleGrid& grid, int32_t want, RemeshOptimizeOptions oo,
                          RemeshResult& r) {
  constexpr double kBelow = 25;
  const double before = remesh_stats(m, r.remesh, false).min_angle_deg;
  const int32_t budget = want + 3 * want / 200 - r.remesh.num_vertices();
  if (!(before < kBelow) || budget <= 0) return;
  Mesh keep = r.remesh;
  std::vector<int32_t> keep_site = r.vertex_site;
  if (split_thin(grid, r.remesh, kBelow, budget, r.vertex_site, oo.pinned) == 0) return;
  if (!oo.pinned.empty()) oo.pinned.resize(static_cast<size_t>(r.remesh.num_vertices()), 0);  // new vertices move
  oo.rounds = 2;
  const RemeshOptimizeStats st = optimize_remesh(m, grid, r.remesh, oo);
  if (remesh_stats(m, r.remesh, false).min_angle_deg > before) {
    r.optimize += st;
    return;
  }
  r.remesh = std::move(keep);
  r.vertex_site = std::move(keep_site);
}

// The dual's optimization on the input, through its grid.
void optimize_on_input(const Mesh& m, const TriangleGrid& grid, const RemeshOptions& o, RemeshResult& r) {
  // Before the splits and collapses change them: one-triangle components.
  r.single_triangles = restore_single_triangles(m, grid, r.remesh);
  // More than 1.5% above the request (repair sites where the topology
  // needed them): the shortest interior edges collapse to it.
  const int32_t want = o.lloyd.sites;
  // The vertices of feature sites stay (remesh_features.hpp); none without features.
  auto pinned = [&] {
    std::vector<uint8_t> p;
    if (r.feature_sites > 0)
      for (int32_t s : r.vertex_site) p.push_back(s < r.feature_sites);
    return p;
  };
  if (r.remesh.num_vertices() * 200 > want * 203)
    collapse_to_count(m, grid, r.remesh, want, r.vertex_site, pinned());
  // More than 1.5% below it (cells that vanished on a coarse input): the
  // longest edges split to it.
  if (r.remesh.num_vertices() * 200 < want * 197) split_to_count(grid, r.remesh, want, r.vertex_site, pinned());
  RemeshOptimizeOptions oo;
  oo.rounds = o.optimize_rounds;
  oo.pinned = pinned();
  oo.slides = feature_slides(r.feature_lines, r.vertex_site, r.feature_sites);  // after the collapses
  r.optimize = optimize_remesh(m, grid, r.remesh, oo);
  split_and_reoptimize(m, grid, want, oo, r);
  // Off the angle targets: vertices from flat, wide regions to thin ones.
  const RebalanceStats rb = rebalance_remesh(m, grid, r.remesh, oo, r.vertex_site);
  r.rebalance_rounds = rb.rounds;
  r.optimize += rb.optimize;
  // Last, the input's farthest vertices pull the remesh to them (median
  // Hausdorff distance of the sample meshes 1.56 -> 1.02%, docs/cvt.md).
  RemeshFidelityOptions fo;
  fo.pinned = std::move(oo.pinned);
  if (!fo.pinned.empty()) fo.pinned.resize(static_cast<size_t>(r.remesh.num_vertices()), 0);  // split vertices move
  r.optimize.moves += pull_to_input(m, grid, r.remesh, fo);
  restore_single_triangles(m, grid, r.remesh);  // again, should a pass have moved one (idempotent)
}

}  // namespace

void assemble_remesh(const Mesh& m, const Mesh& level, const RestrictedDual& dual, const RemeshOptions& o,
                     BatchStopwatch& sw, RemeshResult& r) {
  r.remesh = dual_mesh(level, dual, r.lloyd.sites, r.vertex_site);
  r.dual_s += sw.lap();
  const RemeshStats raw = remesh_stats(m, r.remesh, false);
  r.dual_mean_min_angle_deg = raw.mean_min_angle_deg;
  r.dual_min_angle_deg = raw.min_angle_deg;
  // One grid of the input for the optimization and the Hausdorff distance.
  std::optional<TriangleGrid> grid;
  if (o.optimize_rounds > 0 || o.hausdorff) grid.emplace(m);
  if (o.optimize_rounds > 0) optimize_on_input(m, *grid, o, r);
  r.optimize_s = sw.lap();
  if (o.hausdorff) r.hausdorff_rel = remesh_stats(m, *grid, r.remesh).hausdorff_rel;
  r.hausdorff_s = sw.lap();
}

}  // namespace locus
