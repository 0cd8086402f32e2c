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
//    angle off 2 pi / valence by > 25 % or an edge ratio > 1.6); HeatAverage at
//    shape-regular stars whose valence is not 6 (lattice defects, e.g. an
//    icosphere's corners: a symmetric star has no convexity bias, and there the
//    plain average measured better, logmap_estimator.cpp prepare_center); LogHeat elsewhere.
//    Defaults: LatticeCorrection::Path (at regular valence-6 stars) and recenter.
// Where some (h_k)_j is not positive (non-Delaunay meshes, underflow) the log
// estimators fall back to HeatAverage for that vertex, counted in the stats.
// Corrections after the gradient estimate (LogMapEstimator; defaults in LogMapOptions):
//  * lattice (LatticeCorrection::Star / Ring / Path): map the gradient direction
//    to the normal of the heat kernel's dispersion set (see below; logmap_lattice.cpp,
//    logmap_path.cpp), from the center's star, from the stars of
//    the center and its ring, or (Path, the default) from the stars along the
//    ray to each vertex; applied at regular valence-6 stars only.
//  * recenter: on irregular meshes each vertex's heat carries a factor that does
//    not depend on the source (its mass and weights), whose gradient adds the
//    same vector b to every grad log h_j: an angle error of harmonic 1. b is
//    the center of a least-squares circle through the gradients of the patch
//    vertices beyond the near field (they lie on the boundary of the
//    dispersion set, centrally symmetric), used only when the patch surrounds
//    the center.
//
// Why these defaults, what they cost and what was tried and dropped (with the
// commands that reproduce every figure): docs/logmap.md.
//
// Reference direction: the projection into the tangent plane of the edge from
// i to its lowest-numbered neighbor; e2 = n_i x e1 with n_i on the side of the
// face normals, so consistently oriented triangles keep their orientation.
//
// Thread safety: const after construction; concurrent queries (from oneTBB
// tasks or the caller's threads) each need their own LogMapWorkspace
// (logmap_workspace.hpp). A query
// itself runs on the calling thread only.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "locus/mesh.hpp"
#include "locus/pipelines/geodesic/heat_geodesic.hpp"
#include "locus/pipelines/geodesic/logmap_workspace.hpp"

namespace locus {

enum class LogMapAngle { Auto, LogHeat, LogHeatTwoRing, HeatAverage };

// Plane-wave (dispersion) correction of the log estimators' direction, see above.
// None: the gradient direction itself. Star: dispersion relation of the center's
// own star. Ring: the stars of the center and its one ring summed (an average
// lattice for irregular meshes). Path (the default): per patch vertex j, the
// dispersion relation summed over the stars of the patch vertices near the ray
// from i to j (a sector of the first-pass map, radius below j's), weighted per
// unit length, each star turned into i's tangent plane by the minimal rotation
// of its normal (logmap_path.cpp).
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
  int64_t underflow = 0;         // patch vertices whose heat underflowed (HeatGeodesicWorkspace::underflow)
  double t_no_underflow = 0;     // a t that avoids it (0: none underflowed)
  // Thread CPU time per phase of a localized query, for the bench's breakdown:
  // region (patch + ring + faces), center (sources, estimator), heat plan, heat
  // solve, distance (divergence + Poisson plan and solve; Poisson solve alone in
  // poisson_s), angles (gradients, logs, corrections, output).
  double region_s = 0, center_s = 0, plan_s = 0, heat_s = 0, distance_s = 0, poisson_s = 0, angles_s = 0;
};

class HeatLogMap {
 public:
  // Needs what HeatGeodesic needs (manifold triangle mesh, no zero-area faces).
  // `derived`: m's derived data when the caller has it (see HeatGeodesic).
  explicit HeatLogMap(const Mesh& m, const LogMapOptions& opt = {}, const RunContext& ctx = {},
                      const MeshDerived* derived = nullptr);
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
  // Each step lives in the file named beside it (pipelines/src/geodesic/).
  struct StarFrame;  // logmap_parts.hpp
  // logmap_frame.cpp: vertex normals (eq. 6.2) and the classes of a star.
  void prepare(const Mesh& m, const MeshDerived* derived = nullptr);
  bool irregular_star(int32_t i) const;
  bool defect_star(int32_t i) const;
  // logmap_estimator.cpp: sources and coefficients per center (returns the
  // resolved estimator: Auto replaced by its choice for this center), then
  // the gradient estimate per patch vertex from its heat row f (padded: f
  // holds zeros up to the next whole SIMD batch).
  LogMapEstimator prepare_center(int32_t center, LogMapEstimator e, LogMapWorkspace& ws) const;
  void two_ring_coefficients(int32_t i, const double e1[3], const double e2[3], LogMapEstimatorWorkspace& ew) const;
  void begin_gradients(size_t patch_size, LogMapEstimatorWorkspace& ew, LogMapPathWorkspace& pw) const;
  void vertex_gradient(size_t p, bool is_center, bool is_source, const double* f, bool padded, double h_center,
                       const LogMapEstimator& est, LogMapStats& st, LogMapEstimatorWorkspace& ew,
                       LogMapPathWorkspace& pw) const;
  // logmap_lattice.cpp: dispersion stars; the Star / Ring table from `stars`.
  void add_star_edges(int32_t v, const StarFrame& frame, double weight, double& mass,
                      DispersionStarScratch& star) const;
  void prepare_lattice(const double e1[3], const double e2[3], std::span<const int32_t> stars,
                       LogMapLatticeWorkspace& lw) const;
  // logmap_path.cpp: the Path table around center i from the first-pass angles.
  void path_offsets(std::span<const int32_t> patch, int32_t i, LogMapPathWorkspace& pw) const;
  void add_path_star(int32_t v, double weight, const double n[3], const double e1[3], const double e2[3], double inv_h,
                     double* cell, DispersionStarScratch& star) const;
  // logmap_angles.cpp: corrections, angles and the unit directions; then (u, v).
  void finish_angles(std::span<const int32_t> patch, const LogMapOutput& out, const LogMapEstimator& est,
                     LogMapStats& st, LogMapWorkspace& ws) const;
  static void scale_by_distance(const LogMapOutput& out);
  // logmap_query.cpp: the steps of the two queries (the heat from every
  // source: one wide solve read in the solver's row order, several passes
  // gathered, or full solves) and the head and tail they share.
  LogMapEstimator begin_query(int32_t center, std::span<const int32_t> patch, const LogMapEstimator& estimator,
                              int32_t region_size, LogMapStats& st, LogMapWorkspace& ws) const;
  void solve_heat_one_pass(int32_t lanes, LogMapWorkspace& ws) const;
  void gradients_from_rows(int32_t lanes, int32_t center_local, const LogMapEstimator& est, LogMapStats& st,
                           LogMapWorkspace& ws) const;
  void solve_heat_passes(int32_t lanes, int32_t passes, LogMapWorkspace& ws) const;
  void solve_heat_full(int32_t batches, LogMapWorkspace& ws) const;
  void gradients_from_table(std::span<const int32_t> patch, int32_t center, std::span<const int32_t> row_of,
                            size_t center_row, size_t stride, const LogMapEstimator& est, LogMapStats& st,
                            LogMapWorkspace& ws) const;
  void finish_query(std::span<const int32_t> patch, const LogMapOutput& out, const LogMapEstimator& est,
                    LogMapStats& st, LogMapWorkspace& ws) const;

  LogMapOptions opt_;
  HeatGeodesic geo_;
  HostVector<double> x_, y_, z_;  // positions
  HostVector<double> normal_;     // 3 * n: eq. 6.2 (mean-curvature normal, area normal where it vanishes)
  HostVector<uint8_t> boundary_;  // n: on a boundary edge
};

// Quality of a map over its patch (pipelines/src/geodesic/logmap_patch_quality.cpp).
// Triangles with all three corners in the patch whose (u, v) image has negative
// signed area (the map's orientation is that of the faces). `local` is
// scratch of num_vertices() entries, all -1 between calls.
int64_t count_flipped_triangles(const TriangleGradients& g, std::span<const int32_t> patch,
                                std::span<const double> u, std::span<const double> v, std::vector<int32_t>& local);

// The map's injectivity radius around its center: the largest r such that no
// flipped triangle (as counted above) has all three corners at distance < r,
// i.e. the min over flipped triangles of their farthest corner's distance;
// +infinity when none is flipped. Keeping the patch vertices with distance < r
// gives a flip-free map (users placing decals or textures need to know where
// the map stops being one-to-one). `local` as above.
double injectivity_radius(const TriangleGradients& g, std::span<const int32_t> patch, std::span<const double> u,
                          std::span<const double> v, std::span<const double> distance, std::vector<int32_t>& local);

}  // namespace locus
