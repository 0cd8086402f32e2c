// Smoothed logarithmic (inverse exponential) map by heat diffusion (thesis
// §6.5-6.6, eqs. 6.1, 6.2, 6.7, 6.8; Herholz & Alexa 2019).
//
// For a center i and a patch P: the heat h_k = A^{-1} e_k from i and from each
// one-ring neighbor k of i, all in one exact subset solve (support
// S = {i} ∪ N(i), wanted P ∪ ring(P)) whose lanes (|S| rounded up to a
// multiple of 8, at most 32 per pass: kernels/include/locus/kernels/solve/solve_wide.hpp) share one read
// of every supernode of the plan; more sources take further passes. By
// symmetry of A, (h_k)_j = (h_j)_k: these |S| solves give, for every j in P,
// the heat from j at i and at i's neighbors, i.e. everything the gradient of
// h_j at i needs. That gradient, taken in the triangles around i, projected
// into the tangent plane of the mean-curvature normal n_i (eqs. 6.1, 6.2, 6.7)
// and area-averaged (eq. 6.8), points from i towards j; its angle to a fixed
// reference direction is the angular coordinate. The distance is the heat
// geodesic from i (pipelines/include/locus/pipelines/geodesic/heat_geodesic.hpp, lane 0 of the same solve).
// Polar to Cartesian gives (u, v).
//
// Because the gradient and the average are linear in the values, each center
// has one tangent vector per source k, W_k = sum_faces A_f P grad(phi_k)_f, and the
// direction to j is sum_k W_k f((h_k)_j): 2 * |S| multiply-adds per patch vertex.
//
// Angle estimator (LogMapAngle):
//  * HeatAverage, f = identity: eqs. 6.7/6.8 as in the thesis. The heat from a
//    far vertex j decays like exp(-r_j / sqrt(t)), i.e. by a factor ~e per edge at
//    t = h^2, so across i's star h_j is strongly convex; the piecewise-linear
//    gradient of such values in a lopsided star leans towards its longer or
//    denser side. On regular meshes the star's symmetry cancels this.
//  * LogHeat, f = log: the same average of gradients of log h_j.
//    log h_j ~ -r_j / sqrt(t) + smooth terms is nearly linear over a star, and
//    grad log h = grad h / h has the direction of grad h (Varadhan's transform
//    applied before differentiating). Same solves, same cost.
//  * LogHeatTwoRing: log h_j at the two-ring of i (|S| ~ 19, three 8-lane
//    batches instead of one) and the gradient at i of the least-squares quadratic
//    through them in tangent-plane coordinates. On irregular meshes the
//    discrete heat kernel carries vertex-level noise; a one-ring stencil turns
//    it into an angle distortion (harmonics 1-4 of the azimuth), the wider
//    least-squares stencil averages it down. Vertices j inside the stencil use
//    the one-ring estimator.
//  * Auto (default): LogHeatTwoRing where the star of i is irregular (a corner
//    angle off 2 pi / valence by > 25 % or an edge ratio > 1.6), LogHeat elsewhere.
//    Defaults: LatticeCorrection::Path (at regular stars) and recenter.
// Where some (h_k)_j is not positive (non-Delaunay meshes, underflow) the log
// estimators fall back to HeatAverage for that vertex, counted in the stats.
// Corrections after the gradient estimate (LogMapEstimator; defaults in LogMapOptions):
//  * lattice (LatticeCorrection::Star / Ring / Path): map the gradient direction
//    to the normal of the heat kernel's dispersion set (see below; logmap.cpp,
//    prepare_lattice, path_offsets), from the center's star, from the stars of
//    the center and its ring, or (Path, the default) from the stars along the
//    ray to each vertex; applied at regular stars only.
//  * recenter: on irregular meshes each vertex's heat carries a factor that does
//    not depend on the source (its mass and weights), whose gradient adds the
//    same vector b to every grad log h_j: an angle error of harmonic 1. b is
//    the center of a least-squares circle through the gradients of the patch
//    vertices beyond the near field (they lie on the boundary of the
//    dispersion set, centrally symmetric), used only when the patch surrounds
//    the center.
//
// Measured (mean over centers of the per-center mean error, after the best
// global rotation; geodesic disk of radius 0.5, t = h^2; worst center in
// brackets; `locus-bench logmap-accuracy SURFACE --centers 10`):
//   icosphere level 7 (h = 0.0094), 10 random centers, E_d 1.4e-3:
//     E_a LogHeat 3.9e-3 (5.9e-3), TwoRing 3.9e-3 (5.7e-3), LogHeat + Ring 3.1e-3 (4.4e-3),
//     LogHeat + Star 2.9e-3 (4.4e-3); DEM 2.9e-3 (4.0e-3);
//     vertex 0 (icosahedron corner) 3.2e-3, vertex 13 (edge midpoint) 1.2e-2, with Ring 8.3e-3.
//   random-point sphere 160k (h = 0.010), 10 centers, E_d 3.7e-3 (4.4e-3):
//     E_a LogHeat 4.2e-2 (8.0e-2), TwoRing 2.0e-2 (4.5e-2), TwoRing + recenter 1.7e-2 (2.9e-2),
//     TwoRing + Ring 5.1e-2 (the lattice correction at irregular stars: worse, hence not applied there).
// Why generic centers are worse than the corners (per-center harmonics of the
// error against the azimuth, --dump): at vertex 0 the error is a pure
// harmonic 5 (5e-3), at vertex 13 a harmonic 2 (1.9e-2) that grows with the
// distance, at generic vertices harmonics 1-4. Every estimator shares them
// (one-ring, two-ring, full solves alike): they are in the heat values, not in
// the gradient estimate, the tangent frame or the rotation fit. The discrete
// heat kernel is anisotropic: far from j, h_j is locally a plane wave
// exp(k . x) whose k solves the lattice's dispersion relation; at t = h^2 the
// star spans one decay length, so the set of admissible k is not a disk where
// the triangles are sheared, and the gradient (k) is not parallel to the
// direction of j (the normal of that set at k). Mapping the direction through
// the dispersion relation of the center's ring removes the local part (sheared
// planar lattice: E_a 1.0e-2 -> 3.5e-3, tests/pipelines/logmap.cpp); what
// remains on icospheres grows with the distance: the lattice changes along the
// path and the heat's rays bend, which a correction at the center cannot undo.
// A half lumped, half consistent mass (HeatGeodesicOptions::mass_blend, meant
// to cancel the h^2 / t term of the decay rate) did not help (vertex 13:
// 1.29e-2 against 1.23e-2). The error falls with t (level 6: 2.7e-3 at 2 h^2,
// 1.7e-3 at 4 h^2, 1.1e-3 at 8 h^2).
//
// Session 6: the correction along the ray (LatticeCorrection::Path). The error
// left by the center's correction grew with the distance (icosphere 7, Star:
// 1.2e-3 at r = 0.1-0.2, 3-6e-3 at r = 0.4-0.5, mostly harmonic 2 with a phase
// constant in r) and scales like h^2 / t (E_a 3.0 / 1.7 / 0.97e-3 at t = 1, 2,
// 4 h^2; 4.3 / 3.0 / 3.2e-3 at levels 6 / 7 / 8 with t = h^2): the lattice's
// anisotropy varies coherently over an icosahedron face, and the direction of
// grad log h_j at i is, to first order, the dual direction of the lattice's
// Finsler norm averaged along the ray from j to i (plus a transverse term from
// its variation, not modelled). Summing the stars' dispersion relations along
// the ray (logmap.cpp, path_offsets) instead of the center's alone gives, over
// the same 10 random centers at t = h^2 (`locus-bench logmap-accuracy SPEC
// --centers 10`; tests/pipelines/logmap_accuracy.cpp):
//   icosphere 7:   E_a 1.71e-3 (worst 2.6e-3), E_d 1.40e-3, no flips (Ring: 3.04e-3);
//   bump 150:      E_a 1.11e-3, E_d 1.34e-3 (Ring: 5.44e-3; DEM 5.28e-2, 1.06e-3);
//   random sphere: unchanged, E_a 1.70e-2, E_d 3.73e-3 (its centers are irregular:
//                  no lattice correction there).
//   other resolutions (E_a, default vs Ring + recenter): icosphere 6 2.56e-3 vs
//   4.32e-3, icosphere 8 1.79e-3 vs 3.19e-3; icosphere 7 at t = 2 h^2 0.99e-3 vs
//   1.69e-3. Allowing Path at irregular centers made the random sphere worse
//   (two-ring + Path + recenter 2.0e-2, ~94 flipped triangles), so Auto keeps
//   the lattice correction to regular stars.
// Its cost is per query and linear in the patch: one pass over every patch
// vertex's star into edge moments (degree <= 10) of its (sector, radius) cell,
// then a 1-D Newton per sector and bin. 10k-vertex patch on icosphere 7, thread
// CPU 10-15 ms against 6.5-9 ms with Ring under load 4 (`logmap-accuracy ...
// variants.*.query_cpu_s`; direct exponential sums took 31 ms). Irregular
// centers (most of subdivided armadillo's) skip it with the lattice correction.
//
// Where the "plain §6.5 implementation, E_a 1.1e-3 on icospheres" comes
// from (session 4, full solves, no corrections, radius 0.5, t = h^2): it is the
// thesis estimator (HeatAverage) at vertex 0, an icosahedron corner (valence 5,
// a symmetric star): 1.10e-3 at level 6 (h = 0.019), 1.08e-3 at level 7. At
// generic vertices the same estimator gives 3.3e-3 to 6.4e-3 (level 6: mean of
// 5 centers 5.3e-3; level 7: 4.5e-3), and over the 10 random centers of
// `logmap-accuracy icosphere:7` 4.28e-3. The error hardly falls from level 6
// to level 7 (t = h^2 keeps h^2 / t fixed, so the lattice anisotropy stays),
// and at the corner the log estimators are worse than the plain one (3.2e-3:
// the convexity bias of grad h there happens to cancel part of the
// anisotropy). Before the Path correction no estimator reached 2e-3 over
// random centers at t = h^2 (best: two-ring + Star 2.87e-3, the session-5
// default Auto + Ring + recenter 3.04e-3).
//
// Cost of a localized query (LogMapStats phases, thread CPU; `locus-bench
// logmap` phases_s; 416k vertices, 5 % patch = 21k vertices, two-ring center
// with 19-22 sources, session 5 under load 3-5): region 1.8 ms, heat plan 0.3,
// heat solve 4.2-4.8 (24 lanes; the region's ancestors, 25.8k columns, 1.6k of
// them the root path), distance 4.6-5.4 (Poisson plan + solve 3.3-4.0, one
// lane; divergence ~1.2), angles 2.0-2.5. At 50 %: 11 / 2.5 / 25 / 32 / 23 ms.
// Factor traffic, counted from the plans (kernels/include/locus/kernels/solve/solve_plan.hpp, plan_traffic;
// bench keys factor_traffic_mb, stream_floor_s; session 6, median of 30
// centers): at 5 % the heat solve reads 23.7 MB (17.3 MB distinct: the root
// path is read by both passes), the Poisson solve 34.5 MB (17.3 distinct);
// 34.5 MB distinct in all. This machine streams 23-30 GB/s on one core
// (stream_read_gbs; 512 MB buffer), so the bytes alone take 1.2-1.5 ms, against
// DEM's 6.4 ms: memory bandwidth does not rule out parity (the session-5 note
// said it did, from a 10 GB/s guess). The solves run at 6 GB/s (heat) and
// 12.5 GB/s (Poisson): latency and per-supernode work, not bandwidth, bound
// them; with the non-solve phases (region, plan, divergence, angles: ~5 ms)
// that is where the time to DEM parity is. At 50 %: 110 / 209 MB read, 209 MB
// distinct, floor 7.0 ms against DEM's 65-93 ms.
// Session 7 (`locus-bench logmap ... --query-threads 2`; the machine was loaded
// 2-3.5 by other jobs throughout, so these are indicative):
//  * the wide solve's row loops spilled their accumulators (perf: 11 of 12 in
//    the 24-lane backward loop; GCC assumed the accumulators alias x); with
//    local copies the heat solve fell from ~5.2 to ~3.9 ms at 5 % (same results);
//  * the log of a heat row is taken in registers (a store-forwarding stall on
//    the log buffer took half of the gradient time) and the raw angles with a
//    vector atan2: angles phase 2.3 -> 1.3 ms at 5 %, 15.8 -> 8.4 ms at 25 %;
//  * one thread, 5 %: region 1.9, plan 0.3, heat solve 4.0, distance 4.8
//    (Poisson 3.5), angles 1.3 ms; DEM 6.4-6.9 ms. A one-lane vectorized Poisson
//    kernel, 8-lane Poisson solves, software prefetch of the next supernodes'
//    blocks or of the x rows did not help (same-process A/B): the solves wait
//    on the factor stream, not on arithmetic;
//  * two threads (LogMapWorkspace::threads): the helper's path (the center's
//    heat alone, then the distance) is the longer one. On this VM two threads
//    of AVX-512 FMAs sometimes ran at half speed each and sometimes at full
//    speed (other tenants on the host), and under load 2-3.5 the second
//    thread mostly waits for a core: two threads were as fast as one at 5 %
//    and slower at 25 %. bench JSON phases_2t_wall_s and heat_local_2t_cpu_*_s
//    show the timeline and each thread's CPU time.
//
// Reference direction: the projection into the tangent plane of the edge from
// i to its lowest-numbered neighbor; e2 = n_i x e1 with n_i on the side of the
// face normals, so consistently oriented triangles keep their orientation.
//
// Thread safety: const after construction; concurrent queries each need their
// own LogMapWorkspace.
#pragma once
#include <atomic>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "locus/mesh.hpp"
#include "locus/kernels/parallel/helper_thread.hpp"
#include "locus/kernels/solve/solve_plan.hpp"
#include "locus/kernels/solve/solve_wide.hpp"
#include "locus/pipelines/geodesic/heat_geodesic.hpp"

namespace locus {

enum class LogMapAngle { Auto, LogHeat, LogHeatTwoRing, HeatAverage };

// Plane-wave (dispersion) correction of the log estimators' direction, see above.
// None: the gradient direction itself. Star: dispersion relation of the center's
// own star. Ring: the stars of the center and its one ring summed (an average
// lattice for irregular meshes). Path (the default since session 6): per patch vertex j, the
// dispersion relation summed over the stars of the patch vertices near the ray
// from i to j (a sector of the first-pass map, radius below j's), weighted per
// unit length, each star turned into i's tangent plane by the minimal rotation
// of its normal (logmap.cpp, path_offsets).
enum class LatticeCorrection { None, Star, Ring, Path };

// How a query turns heat values into angles (see above).
struct LogMapEstimator {
  LogMapAngle angle = LogMapAngle::Auto;
  LatticeCorrection lattice = LatticeCorrection::None;
  bool recenter = false;  // remove the direction-independent part of grad log h_j (see above)
};

struct LogMapOptions {
  HeatGeodesicOptions geodesic;  // t = geodesic.t_factor * h^2, Poisson options
  LogMapAngle angle = LogMapAngle::Auto;
  LatticeCorrection lattice = LatticeCorrection::Path;  // Auto applies it at regular stars only
  bool recenter = true;
  LogMapEstimator estimator() const { return {angle, lattice, recenter}; }
};

// Caller memory for one query: each span has one entry per patch vertex.
struct LogMapOutput {
  std::span<double> distance, angle, u, v;
};

struct LogMapStats {
  int32_t sources = 0;          // |S| = |N(i) ∪ {i}|
  int32_t batches = 0;          // groups of 8 lanes (ceil(|S| / 8))
  int32_t passes = 0;           // wide solves over the plan (1 up to 32 sources; localized queries only)
  int32_t region_size = 0;      // |P ∪ ring(P)|
  int32_t angle_fallbacks = 0;  // log estimators: vertices that used HeatAverage
  bool two_ring = false;        // the two-ring estimator was used at this center
  bool recentered = false;       // recenter asked and applied (enough directions around the center)
  // Thread CPU time per phase of a localized query, for the bench's breakdown:
  // region (patch + ring + faces), center (sources, estimator), heat plan, heat
  // solve, distance (divergence + Poisson plan and solve; Poisson solve alone in
  // poisson_s), angles (gradients, logs, corrections, output).
  // With LogMapWorkspace::threads = 2, distance_s is the helper thread's CPU time.
  double region_s = 0, center_s = 0, plan_s = 0, heat_s = 0, distance_s = 0, poisson_s = 0, angles_s = 0, wait_s = 0;
  // LogMapWorkspace::threads = 2, one-pass queries: wall-clock timeline (steady_clock, seconds).
  // serial: query start to the heat solves (region, center, plan), on the caller;
  // center_lane: query start to the end of the helper's solve of the center's heat;
  // helper_start / helper: when the helper's task (that solve, then the distance)
  // began (from the query start) and how long it ran; main: query start to the
  // caller's angles done;
  // join_wait: the caller's wait for the helper after that.
  struct {
    double serial = 0, center_lane = 0, helper_start = 0, helper = 0, main = 0, join_wait = 0;
  } wall2;
};

struct LogMapWorkspace {
  // Threads inside one localized query: 2 runs a persistent helper thread
  // (kernels/include/locus/kernels/parallel/helper_thread.hpp) that solves the center's heat alone (the same
  // numbers as lane 0 of the wide solve: kernels/include/locus/kernels/solve/solve_wide.hpp,
  // solve_planned_lane) and then the distance (divergence and Poisson solve),
  // while this thread makes the wide solve and computes the gradients and
  // angles. They share no writes and do the same arithmetic, so the results
  // are identical to 1 thread.
  int threads = 1;
  std::unique_ptr<HelperThread> helper;  // threads = 2: created on first use, kept across queries
  // threads = 2: the helper solves the center's heat itself beside the wide
  // solve (true), or takes lane 0 of the wide solve when it is done (false).
  bool center_lane_alone = true;
  std::atomic<int> faces_ready{0};  // threads = 2: 0 faces pending, 1 built, 2 abandoned (the caller failed)
  HeatGeodesicWorkspace geo;
  std::vector<int32_t> sources;
  std::vector<int32_t> ring2, sorted_sources;
  std::vector<double> coef1, coef2, phi;  // 2 * |S|: one-ring and two-ring estimator coefficients
  std::vector<double> star;       // lattice corrections' scratch: (ex, ey, w) per star edge in the center's frame
  std::vector<int32_t> star_ends;  // lattice corrections' scratch: far ends of one star's edges
  std::vector<double> lattice;    // lattice correction: direction offset per table angle, empty = none
  std::vector<double> path;       // Path correction: offsets per (sector, radius bin); path_angle: first-pass angles
  std::vector<double> path_angle, path_r;  // first-pass angle and heat radius per patch vertex
  std::vector<double> path_moments;        // Path correction: edge moments per (sector, radius bin)
  double path_rmax = 1;
  std::vector<double> grad;       // 3 per patch vertex: estimated gradient, usable flag
  std::vector<double> theta;      // finish_angles: raw angle per patch vertex, then its gradient's x and y (padded)
  std::vector<double> logrow, rowbuf;  // one heat row and its log, padded to whole SIMD batches
  std::vector<double> cpad;            // estimator coefficients de-interleaved and padded (see begin_gradients)
  std::vector<int32_t> row_owner; // localized: region index of each row of the wide solve's x, -1 elsewhere
  SolvePlan plan;                 // heat plan, reused across queries (no per-query allocation)
  PlanWorkspace plan_ws;
  WideSolveWorkspace wide;         // localized: all sources in one pass (kernels/include/locus/kernels/solve/solve_wide.hpp)
  WideSolveWorkspace lane;         // threads = 2: the center's heat alone, on the helper thread
  std::vector<double> rhs_wide, out_wide, rhs_lane;
  std::vector<double> out8;        // full variant: one 8-lane batch
  std::vector<double> heat;        // localized: region x (lanes rounded up to 8); full: n x |S|; row-major
  std::vector<double> dist_full;   // n, full variant
  std::vector<double> work_full;   // full variant: solve8's work array, kept across queries
};

class HeatLogMap {
 public:
  // Needs what HeatGeodesic needs (manifold triangle mesh, no zero-area faces).
  explicit HeatLogMap(const Mesh& m, const LogMapOptions& opt = {}, const RunContext& ctx = {});
  // With the heat geodesic's factors given (see HeatGeodesic).
  HeatLogMap(const Mesh& m, const LogMapOptions& opt, HeatGeodesicFactors factors);

  const HeatGeodesic& geodesic() const { return geo_; }
  const LogMapOptions& options() const { return opt_; }
  int32_t num_vertices() const { return geo_.num_vertices(); }

  // Localized (exact subset solves). `center` must be in `patch`; patch ids
  // distinct, in range and in the center's connected component (Error(BadUsage)
  // otherwise; the other components receive no heat from the center).
  LogMapStats query(int32_t center, std::span<const int32_t> patch, const LogMapOutput& out,
                    LogMapWorkspace& ws) const {
    return query(center, patch, out, ws, opt_.estimator());
  }
  // The same with the angle estimator chosen per query (for measuring both).
  LogMapStats query(int32_t center, std::span<const int32_t> patch, const LogMapOutput& out, LogMapWorkspace& ws,
                    LogMapAngle angle) const {
    LogMapEstimator e = opt_.estimator();
    e.angle = angle;
    return query(center, patch, out, ws, e);
  }
  LogMapStats query(int32_t center, std::span<const int32_t> patch, const LogMapOutput& out, LogMapWorkspace& ws,
                    const LogMapEstimator& estimator) const;
  // Same map with full solves and the whole-mesh Poisson problem (the baseline
  // of the thesis without localization); results at the patch vertices.
  LogMapStats query_full(int32_t center, std::span<const int32_t> patch, const LogMapOutput& out,
                         LogMapWorkspace& ws) const {
    return query_full(center, patch, out, ws, opt_.estimator());
  }
  LogMapStats query_full(int32_t center, std::span<const int32_t> patch, const LogMapOutput& out,
                         LogMapWorkspace& ws, LogMapAngle angle) const {
    LogMapEstimator e = opt_.estimator();
    e.angle = angle;
    return query_full(center, patch, out, ws, e);
  }
  LogMapStats query_full(int32_t center, std::span<const int32_t> patch, const LogMapOutput& out,
                         LogMapWorkspace& ws, const LogMapEstimator& estimator) const;

  // Unit tangent frame at vertex i: normal n, reference e1, e2 = n x e1 (3 each).
  void frame(int32_t i, double n[3], double e1[3], double e2[3]) const;

 private:
  // Returns the resolved estimator (Auto replaced by its choice for this center).
  LogMapEstimator prepare_center(int32_t center, LogMapEstimator e, LogMapWorkspace& ws) const;
  void prepare_lattice(const double e1[3], const double e2[3], LatticeCorrection lattice, size_t ring1,
                       LogMapWorkspace& ws) const;
  bool irregular_star(int32_t i) const;
  void begin_gradients(size_t patch_size, LogMapWorkspace& ws) const;
  // f: the row's heat values; padded: f holds zeros up to the next whole SIMD batch.
  void vertex_gradient(size_t p, bool is_center, bool is_source, const double* f, bool padded, double h_center,
                       const LogMapEstimator& est, LogMapStats& st, LogMapWorkspace& ws) const;
  // LatticeCorrection::Path: offsets per (sector, radius) from the first-pass angles.
  void path_offsets(std::span<const int32_t> patch, LogMapWorkspace& ws) const;
  static double path_offset_at(const std::vector<double>& table, double th, double r, double rmax);
  void finish_angles(std::span<const int32_t> patch, const LogMapOutput& out, const LogMapEstimator& est,
                     LogMapStats& st, LogMapWorkspace& ws) const;
  static void scale_by_distance(const LogMapOutput& out);

  void prepare(const Mesh& m);  // tangent frames (eq. 6.2)

  LogMapOptions opt_;
  HeatGeodesic geo_;
  std::vector<double> x_, y_, z_;  // positions
  std::vector<double> normal_;     // 3 * n: eq. 6.2 (mean-curvature normal, area normal where it vanishes)
};

// Triangles with all three corners in the patch whose (u, v) image has negative
// signed area (the map's orientation is that of the faces). `local` is
// scratch of num_vertices() entries, all -1 between calls.
int64_t count_flipped_triangles(const TriangleGradients& g, std::span<const int32_t> patch,
                                std::span<const double> u, std::span<const double> v, std::vector<int32_t>& local);

}  // namespace locus
