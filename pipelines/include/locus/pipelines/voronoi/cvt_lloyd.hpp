// Centroidal Voronoi tessellations by Lloyd's method with heat-diffusion cells and
// centroids, localized (thesis §3.7.1; cells §3.4 eq. 3.18, centroids §3.5 and
// "Centroids on faces", localization §3.6 Algorithm 2), isotropic or anisotropic.
//
// prepare: one factorization of M - t L_C (t = t_factor h^2 or absolute).
// Anisotropic (lambda > 0): the mesh is scaled to a unit bounding box (largest side
// 1) and lifted to R^6 by (p, lambda n) with area-weighted vertex normals n; the
// cotan weights, lumped masses and h of the lifted mesh come from its 6-D edge
// lengths (heat_operator_from_positions, kernels/include/locus/kernels/mesh/lifted_metric.hpp), so cells and centroids follow the metric
// that also measures normal variation (thesis: lambda = 0.05).
// iteration: (1) labels = heat Voronoi of the current sites, 8 sites per solve;
// (2) batches of 8 neighboring cells (breadth-first patches of the cell adjacency
// graph, seeded in Morton order of the sites); per cell, its source (the split
// triangles of the cell, computed inside the cell's own task from its vertex stars:
// voronoi_cell_partition.hpp accumulate_cell_load), the heat of that source and its
// hottest point, refined by the quadratic fit (a oneTBB flow graph: an unlimited
// function_node solves batches of 8 cells, a serial node stores each centroid in its
// cell's slot; the new sites are read in cell order). The next labels use the same
// batches and kept sets (the sites are these cells' centroids).
// Per-iteration work outside the per-cell tasks, all O(n) but single cheap passes:
// the labels' top-K arrays and argmax, the cell lists and cell adjacency (one pass
// over the edges), the Morton order and the batch patches (O(sites)).
// Centroid refinement: the quadratic is fitted on fit_rings rings of the hottest
// vertex (the thesis fits one ring; the default 2 averages the piecewise-linear heat
// over ~19 values instead of ~7, so the centroid jumps less when the hottest vertex
// changes), then refitted with Gaussian weights of width fit_sigma one-ring
// distances centered at that first maximizer (heat_centroid.hpp; default 1, 0 = off:
// less jitter at the fixed point, higher dual angles).
// Diffusion time: t = kLloydTFactor h^2 = 4h^2 by default (library, engine Session,
// C API and `locus cvt` alike; the thesis uses h^2, `locus voronoi` keeps h^2): at
// t = h^2 Lloyd stalls on irregular meshes, whose heat bisectors get better with t.
// The measurements behind these defaults, with the commands that reproduce them,
// are in docs/cvt.md.
// Localized solver (default): every solve is the approximate selective solve
// restricted to the union over the batch of the cells, their neighbor cells and
// their neighbors (from the latest labels; before the first labels, the same from
// the initial sites' Dijkstra cells, or with init_cells = false the vertices
// within a Dijkstra radius of init_radius * sqrt(area / (pi N)) of each site). The full
// solver does the same arithmetic with full solves, for comparison.
// After the last iteration the labels of the final sites are computed once more,
// so `label` and `sites` belong together.
//
// Deterministic: seeded initial sites (random_surface_points), order-independent
// reductions; the result is bit-identical for any ctx.threads. Progress is reported
// per iteration ("lloyd"); cancellation is polled between work items.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "locus/mesh.hpp"
#include "locus/run_context.hpp"
#include "locus/sparse_matrix.hpp"
#include "locus/kernels/heat/heat_diffusion.hpp"
#include "locus/kernels/mesh/mesh_derived.hpp"
#include "locus/kernels/heat/surface_point.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/pipelines/voronoi/heat_voronoi.hpp"
// Declared there, part of this header's interface: geodesic_neighborhoods (site
// neighborhoods); heat_operator_from_positions and lifted_positions (the lift).
#include "locus/kernels/mesh/lifted_metric.hpp"
#include "locus/pipelines/voronoi/site_neighborhoods.hpp"

namespace locus {

// Default diffusion time of the CVT's cells and centroids in units of h^2 (see above).
inline constexpr double kLloydTFactor = 4.0;

// The automatic schedule of graph_iterations (LloydOptions): from this many
// vertices on, the first Lloyd iterations run in the graph metric and only the
// last kLargeHeatIterations with heat cells.
inline constexpr int32_t kGraphLloydVertices = 200000;
inline constexpr int32_t kLargeHeatIterations = 3;

struct LloydOptions {
  int32_t sites = 100;       // number of generators (random initial sites)
  int32_t iterations = 10;   // at most (see stop_energy)
  // How many of `iterations` run first in the graph metric (geodesic_lloyd in
  // site_neighborhoods.hpp: one multi-source Dijkstra each, a fraction of a
  // heat iteration's cost on large meshes), the rest with heat cells and
  // centroids. -1 = automatic: on meshes of at least kGraphLloydVertices
  // vertices all but kLargeHeatIterations of them, else none (docs/cvt.md).
  int32_t graph_iterations = -1;
  // Stopping rule: after an iteration whose CVT energy (LloydResult::energy) fell
  // by less than stop_energy times its value (or rose: the discrete centroids'
  // jitter), stop. 0 = always `iterations`. Lloyd's energy falls ~0.3% per
  // iteration after 10 on armadillo with 2,000 sites, ~0.1% after 20 (docs/cvt.md).
  double stop_energy = 0.0;
  uint64_t seed = 1;         // initial sites
  enum class Solver { Local, Full } solver = Solver::Local;
  double t_factor = kLloydTFactor;  // t = t_factor * h^2 unless t_abs > 0 (thesis §3.7: h^2; see above)
  double t_abs = 0.0;
  // Centroid diffusion time as a multiple of h^2, or absolute when t_centroid_abs > 0
  // (both 0: the cells' operator, t above); a second numeric factor on the same
  // symbolic factor.
  double t_centroid_factor = 0.0;
  double t_centroid_abs = 0.0;
  double anisotropy = 0.0;   // lambda of the R^6 lift; 0 = isotropic
  bool refine = true;        // quadratic refinement of centroids (§3.7.1)
  int fit_rings = 2;         // vertex rings of the refinement fit (heat_centroid.hpp; thesis: 1)
  double fit_sigma = 1.0;    // weighted refit of the maximizer (heat_centroid.hpp; 0 = none, as the thesis)
  double init_radius = 4.0;  // first neighborhoods, in units of sqrt(area / (pi N))
  // Localized first labels: the kept sets of the initial sites' graph-geodesic
  // (Dijkstra) cells and their two rings of neighbor cells, batched as every
  // later iteration (one multi-source Dijkstra), instead of a Dijkstra ball of
  // init_radius per site (docs/cvt.md).
  bool init_cells = true;
  // Cell sources from triangles split along the heat bisectors
  // (pipelines/include/locus/pipelines/voronoi/voronoi_cell_partition.hpp) instead of whole vertex stars.
  bool split_faces = true;
  // Count the factor entries the localized solves read (LloydResult::read_fraction);
  // costs a pass over each plan, so off by default.
  bool count_reads = false;
  bool track_quality = false;  // record the dual-angle means of every iteration (LloydResult::mean_angle)
  // Isotropic only: the cells' operator M - t L already factored (e.g. loaded from a
  // factor cache); t_factor and t_abs are then ignored. Not owned; must outlive the call.
  const HeatDiffusion* prepared = nullptr;
  // Keep the final labels' heat (LloydResult::voronoi: the hottest entry of each
  // vertex's top-K list, keep_hottest_only), to add sites later without
  // relabelling everything (heat_voronoi_add).
  bool keep_voronoi = false;
};

struct LloydResult {
  std::vector<SurfacePoint> sites;
  HostVector<int32_t> label;     // per vertex, cell of the final sites
  HeatVoronoi voronoi;            // with keep_voronoi: the diagram behind `label` (top_k = 1)
  double h = 0, t = 0;            // in the operator's metric
  double t_centroid = 0;          // the centroids' diffusion time (t unless set apart)
  double factor_s = 0;            // operator + ordering + symbolic + numeric
  int64_t factor_bytes = 0;       // numeric factor values (both factors with a centroid time of their own)
  double init_s = 0;              // initial sites, graph-metric iterations and first neighborhoods
  int32_t graph_iterations = 0;   // Lloyd iterations run in the graph metric (before iter_s's)
  std::vector<double> iter_s;     // per iteration (labels + centroids)
  double final_labels_s = 0;
  // Phase totals over the iterations: heat Voronoi labels, cells and split triangles,
  // per-site neighborhoods (localized), centroid solves and refinement.
  double labels_s = 0, partition_s = 0, neighborhood_s = 0, centroids_s = 0;
  // Thread CPU time inside the heat solves alone (solve_heat_batch: planning and the
  // solve), summed over batches: labels (the final labels included) and centroids.
  double label_solve_cpu_s = 0, centroid_solve_cpu_s = 0;
  int64_t unreached = 0;          // labels filled by the breadth-first fallback, all iterations
  int64_t empty_cells = 0;        // cells without vertices, all iterations (their sites stay)
  double mean_kept_fraction = 0;  // localized: mean over centroid batches of |kept| / n
  // With count_reads, localized: mean over batches of the factor entries one solve
  // reads (kernels/include/locus/kernels/solve/solve_selective.hpp selective_solve_reads) over what a full
  // solve reads (2 * factor_entries), for the centroid solves and for the label
  // solves of the same batches; 1 / fraction bounds the local/full speed-up of
  // the solves when reading the factor is their cost.
  double centroid_read_fraction = 0, label_read_fraction = 0;
  // Per iteration, for the labels of that iteration and the sites before the move:
  // the Euclidean CVT energy sum_v M_vv |x_v - site(label v)|^2 (R^3, lumped mass);
  // Lloyd with exact centroids never raises it, so it shows convergence.
  std::vector<double> energy;
  std::vector<double> cell_area;   // final cells, triangles split along the bisectors, R^3 metric
  int64_t fallback_faces = 0;      // split triangles cut by vertex labels (heat value missing), all iterations
  std::vector<double> moved;       // RMS site displacement of the move, in units of h (R^3 mean edge)
  std::vector<double> mean_angle;  // with track_quality: mean smallest dual angle (deg)
  std::vector<double> min_angle;   // with track_quality: min smallest dual angle (deg)
  // Per iteration: RMS over the cells of the distance between the heat centroid and
  // the area centroid of the same cell (its source: sum_i b_i x_i / sum_i b_i, exact
  // for the split triangles), tangential (the difference projected off the normal at
  // the heat centroid), in units of h (R^3 mean edge). Diagnostic of the centroid's bias.
  std::vector<double> centroid_bias;
  std::vector<double> centroid_bias_median;  // the median instead of the RMS
};

// Random initial sites (seeded), then `iterations` Lloyd steps.
LloydResult cvt_lloyd(const Mesh& m, const LloydOptions& opt, const RunContext& ctx);
// The same from given initial sites (opt.sites and opt.seed are ignored).
LloydResult cvt_lloyd(const Mesh& m, std::vector<SurfacePoint> initial, const LloydOptions& opt,
                      const RunContext& ctx);
// Both with m's derived data (kernels/include/locus/kernels/mesh/mesh_derived.hpp): edges, h, lumped mass
// and components are taken from d, the mesh check is skipped when d.checked covers it.
LloydResult cvt_lloyd(const Mesh& m, const MeshDerived& d, const LloydOptions& opt, const RunContext& ctx);
LloydResult cvt_lloyd(const Mesh& m, const MeshDerived& d, std::vector<SurfacePoint> initial,
                      const LloydOptions& opt, const RunContext& ctx);

}  // namespace locus
