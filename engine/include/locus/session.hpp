// locus::Session — one mesh and everything derived from it, for embedding
// (issue 9 item 1; README "Embedding").
//
// A Session validates its mesh once, then answers queries: heat geodesic
// distance (thesis §6.4), heat log maps (§6.5–6.6), centroidal Voronoi
// tessellations by Lloyd's method (§3.7), heat values between vertex sets by
// exact subset solves (ch. 4), and region-of-interest deformation with the
// factor-once submesh update (ch. 5). What a query needs is built on first use
// and cached for the positions it was built from:
//   * topology: adjacency, Dijkstra disks (built once);
//   * the heat-method engine per t_factor (heat operator M - tL and Poisson
//     operator -L + eps M, both factored) — serves geodesic distance and log
//     maps;
//   * numeric factors keyed by (operator kind, t), on symbolic factors keyed by
//     the operator's sparsity pattern — serve heat values;
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

#include "locus/mesh.hpp"
#include "locus/mesh_io.hpp"
#include "locus/mesh_view.hpp"
#include "locus/run_context.hpp"
#include "locus/view.hpp"

#include "locus/export.h"

LOCUS_API_BEGIN
namespace locus {

// Diffusion time of the heat operators: t = t_factor * h^2, h the mean edge
// length (Crane et al. and the thesis use t_factor = 1).
struct HeatQuery {
  double t_factor = 1.0;
};

struct LogMapResult {
  std::vector<int32_t> patch;  // the geodesic disk (graph metric), center first
  // Per patch vertex, in patch order: heat geodesic distance, polar angle and
  // Cartesian coordinates (u, v) = distance * (cos, sin)(angle).
  std::vector<double> distance, angle, u, v;
};

struct CvtResult {
  std::vector<int32_t> label;      // per vertex: index of its cell's site
  std::vector<double> site_xyz;    // 3 per site: final site positions
  std::vector<int32_t> site_face;  // per site: face holding it, or -1 when it is a vertex
  std::vector<int32_t> site_vertex;  // per site: that vertex, or -1
  std::vector<double> site_bary;   // 3 per site: barycentric weights in site_face
  int64_t empty_cells = 0;         // cells without vertices over all iterations (their sites stayed)
  int64_t unreached = 0;           // labels filled by the breadth-first fallback
  // With remesh (issue 23; pipelines/.../voronoi/cvt_remesh.hpp): the remeshed
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
struct DeformRequest {
  int32_t roi_seed = 0;
  double roi_fraction = 0.1;  // in (0, 1]
  int32_t handle_vertex = 0;  // must lie in the ROI
  int32_t handle_ring = 1;    // handle = vertices within this many edges of handle_vertex, inside the ROI
  std::array<double, 3> offset{0.0, 0.0, 0.0};
  DeformEnergyKind energy = DeformEnergyKind::Laplacian;
};

struct DeformResult {
  std::vector<double> xyz;  // 3 * nv deformed positions, interleaved
  int32_t roi_size = 0, free_size = 0;
  double columns_updated_fraction = 0;  // of the submesh factor, recomputed rather than copied
  int refinement_steps = 0;
  double residual = 0;  // of the exact Dirichlet system
};

// Counters of work done, for callers and tests that check "computed once".
struct SessionStats {
  int64_t symbolic_analyses = 0;       // orderings + symbolic factors computed by the Session
  int64_t numeric_factorizations = 0;  // numeric factors computed by the Session (heat values)
  int64_t heat_engines = 0;            // geodesic/log-map engines built (each factors 2 operators)
  int64_t deform_operators = 0;        // global deformation factors built
  int64_t positions_version = 0;       // number of set_positions() calls
};

class Session {
 public:
  // Takes the mesh and checks it: finite coordinates, at least one triangle,
  // triangles only, every index in range, manifold, no zero-area faces, no
  // unreferenced vertices (Error(BadInput) naming the first offender and
  // mesh.source). O(nv + nf); builds no operator.
  explicit Session(Mesh mesh);
  // From the host's buffers (float/double positions, uint16/uint32/int32 ids,
  // byte strides): read once into the Session's mesh, the only copy made
  // (mesh_view.hpp). Same checks as Session(Mesh).
  explicit Session(const MeshView& view);
  static Session from_file(const std::string& path, const ReadOptions& opt = {});
  Session(Session&&) noexcept;
  Session& operator=(Session&&) noexcept;
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;
  ~Session();

  int32_t num_vertices() const;
  int32_t num_faces() const;
  double mean_edge_length() const;  // of the current positions
  Mesh mesh() const;                // a copy, with the current positions

  // Builds the heat-method engine for q.t_factor now (queries build it on first use).
  void prepare_heat(const HeatQuery& q = {}, const RunContext& ctx = {}) const;

  // Heat geodesic distance from `source` to every vertex (full solves);
  // +infinity at vertices in another connected component than the source.
  // out.size() must be num_vertices().
  void geodesic_distance(int32_t source, View<double> out, const HeatQuery& q = {},
                         const RunContext& ctx = {}) const;
  std::vector<double> geodesic_distance(int32_t source, const HeatQuery& q = {}, const RunContext& ctx = {}) const;

  // Heat log map of the geodesic disk of round(fraction * nv) vertices (at least
  // 1) around `center`, by exact subset solves from the global factors.
  LogMapResult logmap(int32_t center, double fraction, const HeatQuery& q = {}, const RunContext& ctx = {}) const;

  // Heat values (M - tL)^{-1}_{j,i} for every source i and target j, by exact
  // subset solves (equal to the full solve's entries). Row-major
  // |sources| x |targets|: out[s * |targets| + k] = value at targets[k] of the
  // heat from sources[s]. Ids in range; repeats allowed.
  std::vector<double> heat_values(ConstView<int32_t> sources, ConstView<int32_t> targets,
                                  const HeatQuery& q = {}, const RunContext& ctx = {}) const;

  // Isotropic heat CVT: `sites` seeded random initial sites (1 <= sites <= nv,
  // at least one per connected component), `iterations` >= 0 localized Lloyd
  // steps, t = 4h^2. With `remesh`, also the remeshed surface (CvtResult).
  CvtResult cvt(int32_t sites, int32_t iterations, uint64_t seed, const RunContext& ctx = {},
                bool remesh = false) const;

  // ROI deformation on a copy of the positions (the Session is not changed).
  DeformResult deform(const DeformRequest& req, const RunContext& ctx = {}) const;

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
