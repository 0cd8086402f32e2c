// Vertices moved from flat, wide regions of a remesh to its thin ones
// (pipelines/include/locus/pipelines/voronoi/remesh_rebalance.hpp; thesis §3.7.1).
#include "locus/pipelines/voronoi/remesh_rebalance.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "locus/pipelines/voronoi/remesh_collapse.hpp"
#include "locus/pipelines/voronoi/remesh_quality.hpp"
#include "locus/pipelines/voronoi/remesh_split.hpp"
#include "remesh_vec3.hpp"

namespace locus {

namespace {

constexpr double kMinTarget = 25, kMeanTarget = 50;

bool same_topology(const RemeshStats& a, const RemeshStats& b) {
  return a.manifold == b.manifold && a.genus == b.genus && a.components == b.components &&
         a.boundary_loops == b.boundary_loops;
}

// The angle the triangles below the smallest angle's target lack, weighted
// by their share of the area (degrees): one triangle the remesh cannot open
// (a corner of the input sharper than the target) does not hide the others,
// and a split that halves a thin triangle without opening it yet (a strip
// needs a row of them) does not count twice.
double deficit(const Mesh& m) {
  using namespace remesh_vec3;
  double d = 0, area = 0;
  for (int32_t f = 0; f < m.num_faces(); ++f) {
    const V3 a = pos(m, m.f0[f]), b = pos(m, m.f1[f]), c = pos(m, m.f2[f]);
    const double s = norm(tri_normal(a, b, c));
    d += s * std::max(0.0, kMinTarget - min_angle(a, b, c) * 180 / M_PI);
    area += s;
  }
  return area > 0 ? d / area : 0;
}

struct Score {
  RemeshStats s;
  double deficit = 0;
};

Score score_of(const Mesh& input, const Mesh& remesh) { return {remesh_stats(input, remesh, false), deficit(remesh)}; }

// Better: with triangles below the smallest angle's target, they lack less
// (the smallest angle not lower, the mean down a degree at most); else the
// mean rises and the smallest angle stays at the target.
bool better(const Score& now, const Score& was) {
  if (was.deficit > 0)
    return now.deficit < was.deficit - 1e-9 && now.s.min_angle_deg >= was.s.min_angle_deg - 1e-9 &&
           now.s.mean_min_angle_deg > was.s.mean_min_angle_deg - 1;
  return now.s.min_angle_deg >= kMinTarget && now.s.mean_min_angle_deg > was.s.mean_min_angle_deg + 1e-3;
}

}  // namespace

RebalanceStats rebalance_remesh(const Mesh& input, const TriangleGrid& grid, Mesh& remesh, RemeshOptimizeOptions oo,
                                std::vector<int32_t>& vertex_site, int max_rounds) {
  RebalanceStats st;
  if (!oo.pinned.empty()) return st;  // feature vertices: the collapses would renumber them
  Score was = score_of(input, remesh);
  if (was.deficit == 0 && was.s.mean_min_angle_deg >= kMeanTarget) return st;
  oo.rounds = 2;
  const double start_distance = sampled_hausdorff_distance(input, grid, remesh);
  int32_t budget = std::max(1, remesh.num_vertices() / 50);
  for (int round = 0; round < max_rounds && budget > 0; ++round) {
    if (was.deficit == 0 && was.s.mean_min_angle_deg >= kMeanTarget) break;
    const int32_t n = remesh.num_vertices();
    Mesh keep = remesh;
    std::vector<int32_t> keep_site = vertex_site;
    // Below the smallest angle's target, its triangles; else the thin end of the mean.
    const double below = was.deficit > 0 ? kMinTarget : 40;
    const int32_t splits = split_thin(grid, remesh, below, budget, vertex_site, {}, true);
    if (splits == 0) break;
    const int32_t collapses = collapse_to_count(input, grid, remesh, n, vertex_site, {}, CollapseOrder::Flat);
    const RemeshOptimizeStats os = optimize_remesh(input, grid, remesh, oo);
    const Score now = score_of(input, remesh);
    // Faithfulness: the two-sided distance may not grow by more than 2% of itself.
    const bool faithful = better(now, was) && sampled_hausdorff_distance(input, grid, remesh) <= 1.02 * start_distance;
    if (!same_topology(now.s, was.s) || now.s.vertices > n || !faithful) {
      remesh = std::move(keep);
      vertex_site = std::move(keep_site);
      budget /= 2;  // a round too coarse: smaller steps
      continue;
    }
    ++st.rounds;
    st.splits += splits;
    st.collapses += collapses;
    st.optimize += os;
    was = now;
  }
  return st;
}

}  // namespace locus
