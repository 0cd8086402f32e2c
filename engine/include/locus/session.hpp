// locus::Session — one mesh and everything derived from it, for embedding
// (README "Embedding").
//
// A Session validates its mesh once, then answers queries: heat geodesic
// distance from a vertex or a set of sources (thesis §6.4), heat log maps
// (§6.5–6.6), centroidal Voronoi tessellations by Lloyd's method (§3.7), heat
// Voronoi diagrams, natural-neighbor coordinates and skinning weights (§3.4,
// §3.7.2), heat values, ADF/HKS and heat exchange by exact subset solves
// (ch. 4), region-of-interest deformation with the factor-once submesh update
// (ch. 5), disk and patch parameterizations (§2.6, §4.4), perfect Laplacians
// and self-supporting surfaces (ch. 2). Every pipeline of the `locus` CLI is
// here, with the same numbers for the same arguments (ctest `package`). What a
// query needs is built on first use and cached for the positions it was built from:
//   * topology: adjacency, Dijkstra disks (built once);
//   * the heat-method engine per t_factor (heat operator M - tL and Poisson
//     operator -L + eps M, both factored) — serves geodesic distance and log
//     maps;
//   * the heat operator M - tL factored per t, on symbolic factors keyed by the
//     operator's sparsity pattern — serves Voronoi diagrams, natural neighbors,
//     skinning weights, ADF/HKS, heat exchange and heat values;
//   * -L + eps M factored once — serves the patch parameterizations;
//   * the deformation operator (global factor of -L + eps M or K M^{-1} K) per
//     energy — every deform() query derives its submesh factor from it.
// One factorization serves every later query with the same key. prepare_*()
// builds a key eagerly (e.g. before handing the Session to worker threads).
//
// Thread safety: every const member function may run concurrently with any
// other, from any number of threads. When two threads need the same cache entry
// at once, one computes it and the other waits for it (never computed twice);
// a waiting thread still honours its own RunContext's cancel flag. A query's
// result is bit-identical to the same query run alone, whatever the thread
// counts (the kernels are deterministic and the caches are keyed exactly).
// set_positions() is safe to call concurrently with queries: queries that have
// started finish on the positions (and caches) they started with; queries that
// start after set_positions() returns see the new positions. Only the symbolic
// factors (orderings and supernodal structures, which depend on the pattern,
// not on positions) carry over to the new positions.
//
// A moved-from Session may only be assigned to or destroyed.
//
// Errors: locus::Error with ErrorCode BadUsage (an argument is wrong: vertex id
// out of range, fraction outside (0, 1], ...), BadInput (the mesh is unsuitable),
// Numerical (an operator is not positive definite), Cancelled, ResourceLimit.
// A query that fails leaves the Session usable.
#pragma once
#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "locus/engine/cvt_request.hpp"
#include "locus/engine/deform_request.hpp"
#include "locus/engine/diffusion_requests.hpp"
#include "locus/engine/factor_request.hpp"
#include "locus/engine/geodesic_requests.hpp"
#include "locus/engine/laplacian_requests.hpp"
#include "locus/engine/mesh_info.hpp"
#include "locus/engine/nncoords_request.hpp"
#include "locus/engine/operator_choice.hpp"
#include "locus/engine/param_request.hpp"
#include "locus/engine/skinning_requests.hpp"
#include "locus/engine/voronoi_request.hpp"
#include "locus/mesh.hpp"
#include "locus/mesh_io.hpp"
#include "locus/mesh_view.hpp"
#include "locus/run_context.hpp"
#include "locus/view.hpp"

#include "locus/export.h"

LOCUS_API_BEGIN
namespace locus {

// Diffusion time of the heat operators: t = t_factor * h^2, h the mean edge
// length. t_factor 0 (the default) is each method's own default: 4 for the
// heat method (geodesic distance, log map: the angle error scales like h^2 / t
// and the distance is as accurate, docs/logmap.md; Crane et al. and the thesis
// use 1; 8 on polygon meshes, polygon_heat_geodesic.hpp), 1 for the diffusion
// pipelines.
// The diffusion pipelines (Voronoi, natural neighbors, skinning, ADF/HKS, heat
// exchange, heat values) also take an absolute time: t > 0 overrides t_factor.
// The heat method (geodesic distance, log map) uses t_factor only.
struct LOCUS_API HeatQuery {
  double t_factor = 0.0;  // 0 = the method's default (above)
  double t = 0.0;         // absolute diffusion time; 0 = t_factor * h^2
};

// A point on the surface: a vertex (face < 0), or a face and the barycentric
// weights of its corners in the face's order (weights >= 0 summing to 1).
struct LOCUS_API MeshPoint {
  int32_t face = -1;
  int32_t vertex = -1;
  std::array<double, 3> bary{1.0, 0.0, 0.0};
  static MeshPoint at_vertex(int32_t v) { return MeshPoint{-1, v, {1.0, 0.0, 0.0}}; }
  static MeshPoint in_face(int32_t f, double b0, double b1, double b2) { return MeshPoint{f, -1, {b0, b1, b2}}; }
};

struct LOCUS_API LogMapResult {
  HostVector<int32_t> patch;  // the geodesic disk (graph metric), center first
  // Per patch vertex, in patch order: heat geodesic distance, polar angle and
  // Cartesian coordinates (u, v) = distance * (cos, sin)(angle).
  HostVector<double> distance, angle, u, v;
};

struct LOCUS_API CvtResult {
  HostVector<int32_t> label;       // per vertex: index of its cell's site
  std::vector<double> site_xyz;    // 3 per site: final site positions
  std::vector<int32_t> site_face;  // per site: face holding it, or -1 when it is a vertex
  std::vector<int32_t> site_vertex;  // per site: that vertex, or -1
  std::vector<double> site_bary;   // 3 per site: barycentric weights in site_face
  int64_t empty_cells = 0;         // cells without vertices over all iterations (their sites stayed)
  int64_t unreached = 0;           // labels filled by the breadth-first fallback
  // With remesh (pipelines/.../voronoi/cvt_remesh.hpp): the remeshed
  // surface, one vertex per non-empty cell, made a manifold with the input's
  // topology by added sites (label and the site arrays then cover them too).
  bool remeshed = false;             // a remesh was asked for and is a manifold
  std::vector<double> remesh_xyz;    // 3 per remesh vertex
  std::vector<int32_t> remesh_triangles;  // 3 per triangle, oriented like the input
  std::vector<int32_t> remesh_site;  // per remesh vertex: its site
  int32_t added_sites = 0;
  int64_t remesh_genus = -1;         // summed over components
  int32_t remesh_components = 0, remesh_boundary_loops = 0;
  double mean_min_angle_deg = 0, min_angle_deg = 0, pct_below_30_deg = 0;  // per-triangle smallest angles
  double hausdorff_rel = -1;         // to the input, relative to its bounding-box diagonal
};

enum class DeformEnergyKind { Laplacian, Bilaplacian };

// Move a handle (a vertex and its k-ring) inside a region of interest (the
// breadth-first patch of round(roi_fraction * nv) vertices around roi_seed);
// outside the ROI nothing moves.
struct LOCUS_API DeformRequest {
  int32_t roi_seed = 0;
  double roi_fraction = 0.1;  // in (0, 1]
  int32_t handle_vertex = 0;  // must lie in the ROI
  int32_t handle_ring = 1;    // handle = vertices within this many edges of handle_vertex, inside the ROI
  std::array<double, 3> offset{0.0, 0.0, 0.0};
  DeformEnergyKind energy = DeformEnergyKind::Laplacian;
};

struct LOCUS_API DeformResult {
  std::vector<double> xyz;  // 3 * nv deformed positions, interleaved
  int32_t roi_size = 0, free_size = 0;
  double columns_updated_fraction = 0;  // of the submesh factor, recomputed rather than copied
  int refinement_steps = 0;
  double residual = 0;  // of the exact Dirichlet system
};

// ---- Results of the diffusion, parameterization and chapter-2 pipelines (session_<pipeline>.cpp) ----

// Heat-diffusion Voronoi diagram (thesis §3.4): labels and the bisector curves.
struct LOCUS_API VoronoiResult {
  std::vector<int32_t> label;     // per vertex: the generator with the most heat (eq. 3.18)
  std::vector<double> points;     // 3 per diagram point (on mesh edges, and Voronoi corners)
  std::vector<int32_t> line_offsets;  // polyline k = line_points[line_offsets[k] .. line_offsets[k+1])
  std::vector<int32_t> line_points;   // point ids
  int64_t corners = 0;            // triangles where three cells meet
  int64_t empty_cells = 0;        // generators labelling no vertex
  int64_t vertices_without_heat = 0;  // heat underflowed to 0 there (raise t)
};

// Natural-neighbor (area-stealing) coordinates of one point (thesis §3.7.2).
struct LOCUS_API NaturalNeighborResult {
  std::vector<double> weight;  // one per site, >= 0, summing to 1
  double cell_area = 0;        // area of the point's own cell
  bool at_site = false;        // the point is a site (indicator returned)
  bool degenerate = false;     // the point's cell holds no vertex (indicator of the containing cell)
};

// A prepared natural-neighbor field: the sites' heat Voronoi diagram, computed
// once, serving any number of point queries. Immutable; coordinates() may run
// concurrently from any number of threads. Keeps the Session's mesh and heat
// factor alive (it stays valid after set_positions, on the old positions).
class LOCUS_API NaturalNeighbors {
 public:
  NaturalNeighbors();
  ~NaturalNeighbors();
  NaturalNeighbors(NaturalNeighbors&&) noexcept;
  NaturalNeighbors& operator=(NaturalNeighbors&&) noexcept;
  int32_t num_sites() const;
  // Error(BadUsage) for a point that is not on the mesh.
  NaturalNeighborResult coordinates(const MeshPoint& q) const;
  struct Impl;

 private:
  explicit NaturalNeighbors(std::shared_ptr<const Impl> impl);
  std::shared_ptr<const Impl> impl_;
  friend class Session;
};

struct LOCUS_API SkinningWeightsResult {
  int32_t handles = 0;
  std::vector<double> weight;  // nv * handles, row-major: vertex v's weights at [v * handles, (v + 1) * handles)
  int64_t degenerate_vertices = 0;
  int64_t fallback_faces = 0;
  double max_clamped = 0;
};

// Diagonal entries of (M - tL)^{-1}: Subset walks one etree path per vertex,
// SelectedInversion computes every diagonal entry at once (faster for all vertices).
enum class DiagonalMethod { Subset, SelectedInversion };

// Flip-free parameterization of a disk-like mesh (thesis §2.6): boundary on the
// unit circle by arc length; interior by perfect (Algorithm 1), cotan or uniform weights.
enum class DiskParamMethod { Perfect, Cotan, Uniform };
struct LOCUS_API DiskParamRequest {
  DiskParamMethod method = DiskParamMethod::Perfect;
  int32_t max_iterations = 1000;  // Algorithm 1 (perfect)
  double eps = 1e-6;              // Algorithm 1 tolerance (relative to the diagonal)
};
struct LOCUS_API DiskParamResult {
  std::vector<double> uv;  // 2 * nv, interleaved
  int64_t flipped_faces = 0, degenerate_faces = 0;
  int64_t negative_weights = 0;
  bool converged = true;   // Algorithm 1 (perfect)
  int32_t iterations = 0;
};

// Harmonic parameterization of the breadth-first patch of round(fraction * nv)
// vertices around `center` (thesis §4.4) from the global factor of -L + eps M:
// Neumann (eq. 4.6, an exact subset solve) or Circle (boundary fixed on a circle,
// the patch's factor by the factor-once update; holes of the patch are filled).
enum class PatchBoundary { Neumann, Circle };
struct LOCUS_API PatchParamRequest {
  int32_t center = 0;
  double fraction = 0.1;  // in (0, 1]
  PatchBoundary boundary = PatchBoundary::Neumann;
};
struct LOCUS_API PatchParamResult {
  std::vector<int32_t> vertices;   // global ids of the patch, center first
  std::vector<int32_t> triangles;  // 3 per patch face, indices into `vertices`
  std::vector<double> uv;          // 2 per patch vertex, normalized into the unit disk
  int32_t boundary_vertices = 0;
  int64_t flipped_faces = 0, degenerate_faces = 0;
  int32_t holes_filled = 0;        // Circle only
};

// Algorithm 1 of thesis chapter 2 on the Session's triangle mesh.
struct LOCUS_API PerfectLaplacianRequest {
  bool planar = false;            // use x, y only (one boundary loop needed)
  int32_t max_iterations = 1000;
  double eps = 1e-6;
  bool newton = true;             // false: the multiplicative update of eq. 2.8
};
struct LOCUS_API PerfectLaplacianOutput {
  std::vector<int32_t> edges;     // 2 per unique edge (v0 < v1)
  std::vector<double> weights;    // per edge, normalized to unit 2-norm; 0 where a weight decayed
  std::vector<double> xyz;        // 3 * nv: the embedding (planar) or the embedding aligned onto the input (space)
  bool converged = false;
  int32_t iterations = 0;
  double max_displacement_rel = 0, mean_displacement_rel = 0;
};

// Self-supporting surface (thesis §2.6, eq. 2.12): supports on the boundary.
struct LOCUS_API SelfSupportRequest {
  double load_density = 1.0;
  int32_t max_iterations = 1000;
  double eps = 1e-6;
};
struct LOCUS_API SelfSupportOutput {
  std::vector<int32_t> edges;     // 2 per unique edge (v0 < v1)
  std::vector<double> forces;     // per edge, >= 0, in load units
  std::vector<double> xyz;        // 3 * nv: the equilibrium surface
  bool converged = false;
  int32_t iterations = 0;
  double residual_rel = 0;
};

// Counters of work done, for callers and tests that check "computed once".
struct LOCUS_API SessionStats {
  int64_t symbolic_analyses = 0;       // orderings + symbolic factors computed by the Session
  int64_t numeric_factorizations = 0;  // numeric factors computed by the Session (heat values)
  int64_t heat_engines = 0;            // geodesic/log-map engines built (each factors 2 operators)
  int64_t deform_operators = 0;        // global deformation factors built
  int64_t positions_version = 0;       // number of set_positions() calls
};

// One-shot forms of the chapter-2 pipelines on any polygon mesh (these have
// nothing to cache). The Session methods parameterize_disk, perfect_laplacian
// and self_supporting call them on the Session's faces as given (polygons()). Error(BadInput) names what makes a mesh unsuitable.
LOCUS_API DiskParamResult parameterize_disk_of(const Mesh& mesh, const DiskParamRequest& req = {},
                                               const RunContext& ctx = {});
LOCUS_API PerfectLaplacianOutput perfect_laplacian_of(const Mesh& mesh, const PerfectLaplacianRequest& req = {},
                                                      const RunContext& ctx = {});
LOCUS_API SelfSupportOutput self_supporting_of(const Mesh& mesh, const SelfSupportRequest& req = {},
                                               const RunContext& ctx = {});

// Polygon meshes (quads, mixed, n-gons). A Session takes
// them as they are: each face of more than 3 corners must be a simple polygon
// (Error(BadInput) naming the face otherwise, as the CLI) and is triangulated
// once by ear clipping (kernels/mesh/polygon_triangulation.hpp), keeping the
// vertices: every per-vertex result indexes the caller's vertices. What the CLI
// runs on the polygons themselves the Session does too, with the same numbers:
// geodesic_distance and logmap use the polygon heat method
// (pipelines/.../geodesic/polygon_heat_geodesic.hpp, polygon_logmap.hpp; full
// solves, default t_factor 8, the log map's patch the Dijkstra disk over the
// polygon edges), and parameterize_disk, perfect_laplacian and self_supporting
// the polygon Laplacians. Every other query runs on the triangulation, and the
// face ids of MeshPoint and of results (CvtResult::site_face, random_points)
// are its triangles: mesh() returns it, triangle_polygon() maps each triangle
// to the caller's face, polygons() returns the faces as given.

// How a Session builds its operators (engine/include/locus/engine/operator_choice.hpp).
struct LOCUS_API SessionOptions {
  // auto (default): the cotan operator on a clean manifold mesh, bit for bit as
  // without options; the robust one when the mesh has defects. cotan: the checks
  // below refuse a mesh with defects. robust: always the robust operator.
  OperatorChoice mesh_operator = OperatorChoice::Auto;
  // With auto (or cotan and this flag: a caller that resolved auto itself, as
  // the CLI's loader does, and passes cotan for a clean mesh), a geodesic query
  // whose cotan heat method fails numerically is answered on the robust
  // operator and says so (GeodesicReport::operator_fallback).
  bool cotan_chosen_by_auto = false;
  // The caller never runs two queries at once on this Session (the CLI, one
  // command per process): the cvt command then frees the mesh's edge incidence
  // while its operator is factored and Lloyd's iterations run, which do not
  // read it, and rebuilds it for the dual (25 MB less at the peak of a
  // 416k-vertex remesh, one edge incidence more to build). Concurrent queries
  // on an exclusive Session are undefined.
  bool exclusive = false;
};

class LOCUS_API Session {
 public:
  // Takes the mesh and checks it: finite coordinates, at least one face, every
  // index in range, simple polygons (triangulated, above), manifold, no
  // zero-area faces, no unreferenced vertices (Error(BadInput) naming the
  // first offender and mesh.source). O(nv + nf); builds no operator.
  explicit Session(Mesh mesh);
  // With the operator choice: auto or robust take meshes with non-manifold
  // edges or vertices, zero-area or needle faces, inconsistent orientation or
  // unreferenced vertices (checked: finite coordinates, a face, indices in
  // range, triangles or simple polygons). On the robust operator, geodesic
  // distance (single source, sets, the geodesic request, localized included),
  // heat values and the diffusion queries run on the intrinsic triangulation of
  // the tufted cover; unreferenced vertices get NaN distances; logmap refuses
  // (Error(BadInput)); a polygon mesh then runs on its triangulation.
  Session(Mesh mesh, const SessionOptions& opt);
  // From the host's buffers (float/double positions, uint16/uint32/int32 ids,
  // byte strides): read once into the Session's mesh, the only copy made
  // (mesh_view.hpp). Same checks as Session(Mesh).
  explicit Session(const MeshView& view);
  // A polygon mesh from the host's buffers (mesh_view.hpp), as Session(Mesh).
  explicit Session(const PolygonMeshView& view);
  explicit Session(const MeshView& view, const SessionOptions& opt);
  explicit Session(const PolygonMeshView& view, const SessionOptions& opt);
  static Session from_file(const std::string& path, const ReadOptions& opt = {});
  static Session from_file(const std::string& path, const ReadOptions& opt, const SessionOptions& so);
  Session(Session&&) noexcept;
  Session& operator=(Session&&) noexcept;
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;
  ~Session();

  // The operator the Session runs on and why (the defects found; auto and robust).
  OperatorReport operator_report() const;
  // Sizes, topology and defects of the mesh as given (its polygons for a
  // polygon mesh), with the current positions (engine/mesh_info.hpp).
  MeshInfo info() const;

  int32_t num_vertices() const;
  int32_t num_faces() const;        // triangles of mesh() (of the triangulation for a polygon mesh)
  double mean_edge_length() const;  // of the current positions (of mesh()'s triangles)
  Mesh mesh() const;                // a copy of the triangle mesh, with the current positions
  // Polygon meshes (above): whether the mesh given had a face of more than 3
  // corners; its faces as given (a copy, current positions; mesh() for a
  // triangle mesh) and their count; per triangle of mesh() the face it belongs to.
  bool has_polygons() const;
  Mesh polygons() const;
  int32_t num_polygons() const;
  std::vector<int32_t> triangle_polygon() const;

  // Builds the heat-method engine for q.t_factor now (queries build it on first use;
  // on a polygon mesh the polygon heat method's, which geodesic_distance and logmap use).
  void prepare_heat(const HeatQuery& q = {}, const RunContext& ctx = {}) const;

  // Heat geodesic distance from `source` to every vertex (full solves);
  // NaN (no value, as in every output format and the C API) at vertices in
  // another connected component than the source. Polygon meshes: the polygon
  // heat method (`locus geodesic` on the same file, bit for bit).
  // out.size() must be num_vertices().
  void geodesic_distance(int32_t source, View<double> out, const HeatQuery& q = {},
                         const RunContext& ctx = {}) const;
  std::vector<double> geodesic_distance(int32_t source, const HeatQuery& q = {}, const RunContext& ctx = {}) const;

  // Heat log map of the geodesic disk of round(fraction * nv) vertices (at least
  // 1) around `center`, by exact subset solves from the global factors.
  // Polygon meshes: the polygon log map with full solves on the Dijkstra disk
  // over the polygon edges (`locus logmap` on the same file, bit for bit).
  LogMapResult logmap(int32_t center, double fraction, const HeatQuery& q = {}, const RunContext& ctx = {}) const;

  // The `geodesic` and `logmap` commands with every option of the CLI
  // (engine/include/locus/engine/geodesic_requests.hpp): localized geodesic
  // distance (fraction < 1), the time as text or t_factor, the log map's
  // methods and estimator choices, clip_injective, the factor cache, and the
  // statistics the CLI reports. `locus geodesic` / `locus logmap` call these.
  GeodesicReport geodesic(const GeodesicRequest& req, const RunContext& ctx = {}) const;
  LogmapReport logmap(const LogmapRequest& req, const RunContext& ctx = {}) const;
  // The `adf`, `hks` and `heat` commands (engine/include/locus/engine/
  // diffusion_requests.hpp), with the command's own factors (the factor cache
  // files of the request); `locus adf|hks|heat` call these.
  HeatSignatureReport adf(const AdfRequest& req, const RunContext& ctx = {}) const;
  HeatSignatureReport hks(const HksRequest& req, const RunContext& ctx = {}) const;
  HeatReport heat(const HeatRequest& req, const RunContext& ctx = {}) const;
  // The `nncoords` command (engine/include/locus/engine/nncoords_request.hpp).
  NncoordsReport nncoords(const NncoordsRequest& req, const RunContext& ctx = {}) const;
  // The `param` command (engine/include/locus/engine/param_request.hpp):
  // the disk (faces as given) or a patch, with the CLI's statistics.
  ParamReport param(const ParamRequest& req, const RunContext& ctx = {}) const;
  // The `perfect-laplacian` and `selfsupport` commands (engine/include/locus/
  // engine/laplacian_requests.hpp), on the faces as given.
  PerfectLaplacianCommandReport perfect_laplacian(const PerfectLaplacianCommandRequest& req,
                                                  const RunContext& ctx = {}) const;
  SelfSupportCommandReport self_supporting(const SelfSupportCommandRequest& req, const RunContext& ctx = {}) const;

  // Heat values (M - tL)^{-1}_{j,i} for every source i and target j, by exact
  // subset solves (equal to the full solve's entries). Row-major
  // |sources| x |targets|: out[s * |targets| + k] = value at targets[k] of the
  // heat from sources[s]. Ids in range; repeats allowed.
  std::vector<double> heat_values(ConstView<int32_t> sources, ConstView<int32_t> targets,
                                  const HeatQuery& q = {}, const RunContext& ctx = {}) const;

  // Isotropic heat CVT: `sites` seeded random initial sites (1 <= sites <= nv,
  // at least one per connected component; more than nv with `remesh`, whose
  // cells run on a midpoint subdivision), `iterations` >= 0 localized Lloyd
  // steps, t = 4h^2. With `remesh`, also the remeshed surface (CvtResult).
  // The cached tier: the cells' operator is built once per positions and kept.
  CvtResult cvt(int32_t sites, int32_t iterations, uint64_t seed, const RunContext& ctx = {},
                bool remesh = false) const;
  // The `cvt` command (engine/include/locus/engine/cvt_request.hpp): every
  // option of the CLI, the command's own factor of the cells' operator (the
  // factor cache files of the request), the remesh and the statistics the
  // CLI reports; writes the request's labels and sites_out files.
  CvtReport cvt(const CvtRequest& req, const RunContext& ctx = {}) const;

  // The `factor` command (engine/include/locus/engine/factor_request.hpp): the
  // request's matrix (heat or regularized Laplacian, cotan) ordered, analyzed,
  // factored (or loaded) and solved `repeat` times, with the timings and
  // residuals the CLI reports. Its own factor, not the Session's caches. The
  // matrices are the cotan ones whatever the Session's operator choice (the
  // command measures the numeric core on the mesh's own operator; a mesh with
  // defects is refused with Error(BadInput) naming the first).
  FactorCommandReport factor(const FactorCommandRequest& req, const RunContext& ctx = {}) const;

  // ROI deformation on a copy of the positions (the Session is not changed).
  DeformResult deform(const DeformRequest& req, const RunContext& ctx = {}) const;
  // The `deform` command (engine/include/locus/engine/deform_request.hpp):
  // every option of the CLI and its statistics. With compare_with_refactor
  // (what `locus deform` reports) also the baseline: the free vertices'
  // block factored from scratch and solved again.
  DeformCommandReport deform(const DeformCommandRequest& req, const RunContext& ctx = {},
                             bool compare_with_refactor = false) const;

  // ---- Diffusion, parameterization and chapter-2 pipelines. Each reuses the Session's caches: the
  // heat operator M - tL is factored once per t and serves Voronoi diagrams,
  // natural neighbors, skinning weights, ADF/HKS, heat exchange and heat
  // values alike; -L + eps M once for the patch parameterizations. Each
  // distinct t keeps its factor (memory ~ one Cholesky factor per t) until
  // set_positions() or the Session's end. ----

  // Heat geodesic distance from a set of sources (vertices and points on faces;
  // thesis §6.4.1 with the heat of all sources at once, as Crane et al. and
  // CGAL's Heat_method_3): per connected component the distance is shifted so
  // that its minimum over the component's sources is 0; NaN (no value) in
  // components without a source. At least one source; out.size() == num_vertices().
  void geodesic_distance(ConstView<MeshPoint> sources, View<double> out, const HeatQuery& q = {},
                         const RunContext& ctx = {}) const;
  std::vector<double> geodesic_distance(ConstView<MeshPoint> sources, const HeatQuery& q = {},
                                        const RunContext& ctx = {}) const;
  std::vector<double> geodesic_distance_from_vertices(ConstView<int32_t> sources, const HeatQuery& q = {},
                                                      const RunContext& ctx = {}) const;

  // `count` points uniformly distributed by area (splitmix64 from `seed`: the
  // same on every platform; `locus voronoi --random N --seed S` uses these).
  std::vector<MeshPoint> random_points(int32_t count, uint64_t seed) const;

  // Heat Voronoi diagram of 1..nv generators (default t = h^2).
  VoronoiResult voronoi(ConstView<MeshPoint> generators, const HeatQuery& q = {},
                        const RunContext& ctx = {}) const;
  // The `voronoi` command (engine/include/locus/engine/voronoi_request.hpp):
  // every option of the CLI, the command's own factor of M - tL (the factor
  // cache files of the request) and the statistics the CLI reports.
  VoronoiCommandReport voronoi(const VoronoiCommandRequest& req, const RunContext& ctx = {}) const;

  // Natural-neighbor coordinates: prepared field (many queries) and one-shot.
  NaturalNeighbors prepare_natural_neighbors(ConstView<MeshPoint> sites, const HeatQuery& q = {},
                                             const RunContext& ctx = {}) const;
  NaturalNeighborResult natural_neighbor_coordinates(ConstView<MeshPoint> sites, const MeshPoint& point,
                                                     const HeatQuery& q = {}, const RunContext& ctx = {}) const;

  // Skinning weights of handles at every vertex (natural-neighbor coordinates of the vertices).
  SkinningWeightsResult skinning_weights(ConstView<MeshPoint> handles, const HeatQuery& q = {},
                                         const RunContext& ctx = {}) const;
  // Skinning weights with every option (engine/include/locus/engine/skinning_requests.hpp):
  // handles as vertex sets or bones, the sampled method (default) or exact.
  SkinningReport skinning(const SkinningRequest& req, const RunContext& ctx = {}) const;

  // Auto-diffusion function (M - tL)^{-1}_vv at `vertices` (empty: all vertices, in order).
  std::vector<double> auto_diffusion(ConstView<int32_t> vertices, const HeatQuery& q = {},
                                     DiagonalMethod method = DiagonalMethod::Subset,
                                     const RunContext& ctx = {}) const;
  // Heat kernel signature: out[k * times.size() + j] = ADF at vertices[k] (all when empty) for times[j].
  std::vector<double> heat_kernel_signature(ConstView<HeatQuery> times, ConstView<int32_t> vertices,
                                            DiagonalMethod method = DiagonalMethod::Subset,
                                            const RunContext& ctx = {}) const;
  // Pairwise heat exchange (thesis §4.6): unit heat at every source (repeats add),
  // one step of M - tL; out[k] = heat at targets[k]. Both sets non-empty.
  std::vector<double> heat_exchange(ConstView<int32_t> sources, ConstView<int32_t> targets,
                                    const HeatQuery& q = {}, const RunContext& ctx = {}) const;

  DiskParamResult parameterize_disk(const DiskParamRequest& req = {}, const RunContext& ctx = {}) const;
  PatchParamResult parameterize_patch(const PatchParamRequest& req, const RunContext& ctx = {}) const;

  PerfectLaplacianOutput perfect_laplacian(const PerfectLaplacianRequest& req = {}, const RunContext& ctx = {}) const;
  SelfSupportOutput self_supporting(const SelfSupportRequest& req = {}, const RunContext& ctx = {}) const;

  // The prepared tier, built eagerly (queries build them on first use): the
  // heat operator M - tL for q (the diffusion pipelines) and -L + eps M (the
  // patch parameterizations). prepare_heat() above builds the heat method's.
  void prepare_diffusion(const HeatQuery& q = {}, const RunContext& ctx = {}) const;
  void prepare_patch_parameterization(const RunContext& ctx = {}) const;

  // Unique edges of the triangles; of the faces as given for a polygon mesh
  // (the edges perfect_laplacian and self_supporting return).
  int64_t num_edges() const;

  // New positions, 3 * num_vertices() interleaved doubles, same connectivity.
  // Checks finiteness and that no face becomes degenerate (Error(BadInput),
  // the Session keeps its old positions then). Drops every cache that depends
  // on positions; keeps the symbolic factors.
  void set_positions(ConstView<double> xyz);

  SessionStats stats() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace locus
LOCUS_API_END
