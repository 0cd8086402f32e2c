// Heat geodesic distance, whole-mesh and localized to a patch (thesis §6.4.1,
// eqs. 6.3-6.6, after Crane et al. 2013; localization §6.4.2 with the exact
// subset solves of chapter 4).
//
// prepare (the constructor): t = t_factor * h^2 (h = mean edge length), one
// METIS ordering and one symbolic factor for the shared pattern, numeric
// factors of the heat operator M - t L_C (eq. 6.3) and of -L_C + eps M (the
// regularized Poisson operator of eq. 6.6), per-triangle gradient bases (eq. 6.4).
// query: heat h = A^{-1} e_source; per triangle X = -grad h / |grad h| (eq. 6.5);
// integrated divergence b = D X; (-L_C + eps M) d = b (eq. 6.6, the sign of
// mesh_gradient.hpp); d shifted so that d(source) = 0.
//
// Localized query on a patch P (the caller's vertex set, containing the source):
//  * heat: exact subset solve, support {source}, wanted = P ∪ ring(P) (the
//    vertices of the triangles touching P) — the same numbers as a full solve;
//  * divergence: only from the triangles T(P) with at least one vertex in P;
//  * Poisson: exact subset solve, wanted = P. The right-hand side is where the
//    approximation lies: the true b also has entries outside P, which the
//    localized solve cannot know without the heat outside P ∪ ring.
//    PoissonRhs::Truncated keeps b on P only (the rest treated as zero, §6.4.2
//    as stated). Its entries do not sum to zero, and the regularized Laplacian
//    turns the net source into a constant plus a sink spread uniformly over the
//    whole surface, which bends d inside P (on a unit sphere with a geodesic
//    disk of radius 0.5: the gradient is off by ~0.12 r).
//    PoissonRhs::BoundaryFlux (default) uses the divergence of X restricted to
//    T(P): patch vertices get their complete divergence, ring vertices the
//    partial one, i.e. the flux of X through the patch boundary. It sums to zero
//    exactly and, by Gauss' law, leaves a radially symmetric field exact inside
//    P; what remains is the effect of the divergence outside T(P) on the
//    Helmholtz projection inside, which is small when X is nearly curl-free.
//    Both are measured against the full solve in tests/pipelines/geodesic/heat_geodesic.cpp
//    and by `locus-bench logmap`.
//  * Rim (HeatGeodesicOptions::level_set_rim, default on, with BoundaryFlux):
//    the whole-mesh solve of a truncated field is a transmission problem: the
//    potential outside T(P) is harmonic with the values on the cut, and its
//    normal derivative adds to the flux. Only where the cut is a level set of
//    the distance is it constant outside and the solution exact inside; the
//    patches users ask for (Dijkstra disks in the graph metric, hexagons on an
//    icosphere; one-sided patches) are not, and their outer tenth was bent
//    (icosphere 7, 6 % disk: E_d 2.7e-2 there against 1.3e-3 inside). So X is
//    cut at a level set of the heat, rho = -log h <= the ring's smallest rho
//    (rho is the distance up to a smooth radial profile and the lattice's
//    ~1e-3 anisotropy), with the share of each face inside it, and the patch
//    vertices beyond that level set take the value whose piecewise-linear
//    gradient best fits X in their faces with two known corners (the Poisson
//    step's least squares, one vertex at a time in increasing rho). Outer band
//    2.3e-3, localized within 7e-4 of the full solve (docs/logmap.md, "Rim").
// Per-triangle direction (HeatGeodesicOptions::log_heat_gradient, default on):
// the normalized gradient of log h instead of h. Normalization makes the two
// equal in the continuum; on the mesh, h falls by a factor ~e per edge at
// t = h^2, so its piecewise-linear gradient in a triangle leans towards the
// hottest corner, while log h is nearly linear there. Measured E_d (unit
// icosphere level 6, geodesic disk of radius 0.5): 3.1e-3 with grad h (Crane
// et al.), 2.0e-3 with grad log h. Triangles with a non-positive corner value
// fall back to grad h.
// Cost of a localized query: the reach of {source} and of P ∪ ring in the
// etree, plus O(|P| + |ring|) for gradients and divergence; nothing of size n
// is touched except O(#supernodes) bytes cleared by the plan builder.
//
// Several connected components: both operators stay SPD (M regularizes each
// component's block of the heat operator, eps M that of the Poisson operator),
// but heat never crosses components, so a vertex in another component than the
// source has no geodesic path to it: its distance is +infinity (whole-mesh and
// localized queries alike), never a finite number.
//
// Heat values decay like exp(-r / sqrt(t)); beyond ~700 sqrt(t) they underflow
// to 0, the gradient vanishes and those triangles contribute no direction
// (Crane et al. note the same limit): keep patches within that radius. Every
// query counts the output vertices where that happened and the t that would
// avoid it (HeatGeodesicWorkspace::underflow, t_no_underflow; the CLI warns).
//
// Thread safety: after construction every member is const; queries may run
// concurrently, each thread with its own HeatGeodesicWorkspace.
#pragma once
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "locus/kernels/mesh/mesh_derived.hpp"
#include "locus/kernels/mesh/robust_laplacian.hpp"
#include "locus/kernels/solve/solve_plan.hpp"
#include "locus/kernels/solve/solve_sparse.hpp"
#include "locus/kernels/factor/supernodal_factor.hpp"
#include "locus/mesh.hpp"
#include "locus/run_context.hpp"
#include "locus/kernels/mesh/mesh_gradient.hpp"

namespace locus {

struct HeatGeodesicOptions {
  // Diffusion time t = t_factor * h^2. Crane et al. recommend 1; 4 is the
  // default for accuracy: the log map's angle error comes from the lattice's
  // anisotropy, which scales like h^2 / t, while the distance stays as accurate
  // and a query costs the same at any t (docs/logmap.md, "Defaults").
  double t_factor = 4.0;
  // eps of -L_C + eps M: eps = poisson_rel * mean(diag(-L_C)) / area, i.e. the
  // last pivot of the factorization is about poisson_rel of a typical diagonal
  // entry, whatever the vertex count. Why so small: eps damps each eigenmode of
  // the solution by eps / (lambda + eps), and the distance lives mostly in the
  // lowest ones (unit sphere: lambda_1 = 2). The earlier eps = 1e-6 trace(-L_C) /
  // trace(M) (kernels/include/locus/kernels/mesh/mesh_operators.hpp) grew with n:
  // 0.045 on a 164k icosphere, a 2.2 % shrink of every distance (mean error 0.028
  // over the sphere, 0.0013 now; docs/logmap.md, "Far field"). Zero-sum right-hand
  // sides lose nothing to the small pivot but a constant, which the shift removes.
  double poisson_rel = 1e-5;
  enum class PoissonRhs { BoundaryFlux, Truncated };
  PoissonRhs poisson_rhs = PoissonRhs::BoundaryFlux;  // localized queries only, see above
  bool log_heat_gradient = true;  // direction of grad log h instead of grad h per triangle, see above
  // Mass matrix of the heat operator: (1 - mass_blend) lumped + mass_blend consistent
  // (see heat_geodesic.cpp, blend_mass: meant to cancel the leading h^2 / t term
  // of the discrete decay rate). 0 = the lumped mass of Crane et al. Measured at
  // 0.5: no gain in the log map's angles (icosphere level 7, vertex 13: E_a
  // 1.29e-2 against 1.23e-2), so off. The CLI's factor cache labels the heat
  // factor by t only: a cache made with another mass_blend would be accepted.
  double mass_blend = 0.0;
  // Distances below zero by at most dip_tolerance_h * h (h: mean edge length)
  // on at most 1% of the output vertices are set to 0 and counted
  // (HeatGeodesicWorkspace::dips) instead of refused; 0 refuses every dip.
  double dip_tolerance_h = 0.0;
  // Localized queries with PoissonRhs::BoundaryFlux: truncate X at a level set
  // of the heat (rho = -log h <= the ring's smallest rho) instead of at the
  // patch's own boundary, and continue the distance beyond it to the rest of
  // the patch by least squares along X (see above, "Rim"). Off: the patch boundary.
  bool level_set_rim = true;
};

// The vertices and triangles a localized query works on. Built by
// HeatGeodesic::build_region, reset by release_region (the n-sized index array
// is all -1 between queries, so a query touches only its region).
struct PatchRegion {
  int32_t patch_size = 0;
  HostVector<int32_t> verts;      // the patch (caller's order), then its one ring
  HostVector<int32_t> faces;      // faces with at least one patch vertex, ascending
  HostVector<int32_t> face_local;  // 3 per face: its corners' indices into verts (no lookups in `local` later)
  HostVector<int32_t> local;      // n: index into verts, -1 elsewhere
  HostVector<int32_t> order;      // the patch in ascending vertex order (scratch of build_region)
  HostVector<uint64_t> bits;      // n bits, all zero between queries (scratch of build_region)
  HostVector<uint64_t> face_bits;  // one bit per face, all zero between queries (scratch of build_region)
};

struct HeatGeodesicWorkspace {
  SolveWorkspace heat, poisson;
  SolvePlan heat_plan, poisson_plan;  // reused across queries: planning allocates nothing once warm
  PlanWorkspace plan_ws;
  PatchRegion region;
  HostVector<double> h, b, x, logh;  // per region vertex (or per vertex for full queries)
  HostVector<double> hlb;            // localized divergence: {h, log h, b, pad} per region vertex
  HostVector<double> rho;            // level-set rim: -log h per region vertex
  HostVector<int32_t> rim_order, rim_pos, rim_offsets, rim_faces, rim_later;  // level-set rim: continuation
  HostVector<uint8_t> rim_known;
  double poisson_s = 0;               // thread CPU time of the last localized Poisson plan + solve (reporting)
  // Set by every query: output vertices whose heat underflowed (below the
  // smallest normal double: no direction there, the distance is interpolated)
  // and, when there are any, a diffusion time that keeps the heat above
  // e^-600 over the output's largest distance (heat decays like
  // exp(-d / sqrt t)); 0 when none underflowed.
  int64_t underflow = 0;
  double t_no_underflow = 0;
  // Set by every query with HeatGeodesicOptions::dip_tolerance_h > 0: vertices
  // whose distance dipped below zero within the tolerance, set to 0, and the deepest dip.
  int64_t dips = 0;
  double deepest_dip = 0;
};

// The two factors of a HeatGeodesic, made elsewhere (e.g. loaded from a factor
// cache): M - tL_C with t = t_factor h^2 and -L_C + eps M (poisson_rel), on one
// symbolic factor of this mesh's pattern (HeatGeodesic::operators builds them).
struct HeatGeodesicFactors {
  NumericFactor heat, poisson;
};

class HeatGeodesic {
 public:
  // Needs a manifold triangle mesh without zero-area faces, needles (an angle
  // within 1e-6 rad of 0 or pi; see heat_geodesic.cpp for the measured loss of
  // accuracy) or unreferenced vertices (Error(BadInput) naming the element
  // otherwise); boundaries are
  // allowed (natural boundary conditions). Factorization runs on ctx's threads.
  // `derived`, when given, is m's derived data (a Session's): its components and
  // h are used instead of deriving them again, its checks instead of repeating them.
  explicit HeatGeodesic(const Mesh& m, const HeatGeodesicOptions& opt = {}, const RunContext& ctx = {},
                        const MeshDerived* derived = nullptr);
  // The heat method on the robust Laplacian R of m (kernels/.../robust_heat_operators.hpp):
  // M - tL and -L + eps M of the intrinsic Delaunay triangulation of m's tufted
  // cover, and the gradient and divergence on its intrinsic triangles. Takes any
  // triangle soup: non-manifold edges and vertices, zero-area and needle faces,
  // inconsistent orientation; a vertex in no triangle is a component of its own
  // (+infinity from every other source). mass_blend must be 0.
  HeatGeodesic(const Mesh& m, const RobustOperators& R, const HeatGeodesicOptions& opt, const RunContext& ctx = {},
               const MeshDerived* derived = nullptr);
  // The same with given factors instead of factoring (Error(BadUsage) when their
  // size or pattern is not this mesh's; that they hold these t / eps values is the
  // caller's to check, as the factor cache does with its labels).
  HeatGeodesic(const Mesh& m, const HeatGeodesicOptions& opt, HeatGeodesicFactors factors);
  // The operators it factors: heat = M - t L_C, poisson = -L_C + eps M; returns t.
  static double operators(const Mesh& m, const HeatGeodesicOptions& opt, CscMatrix& heat, CscMatrix& poisson);
  // -L_C + eps M with eps from opt.poisson_rel (see HeatGeodesicOptions).
  static CscMatrix poisson_operator(const Mesh& m, const HeatGeodesicOptions& opt, const EdgeIncidence* inc = nullptr);

  int32_t num_vertices() const { return grad_.nv; }
  double mean_edge_length() const { return h_; }
  double time() const { return t_; }
  const HeatGeodesicOptions& options() const { return opt_; }
  const TriangleGradients& gradients() const { return grad_; }
  const NumericFactor& heat_factor() const { return heat_; }
  const NumericFactor& poisson_factor() const { return poisson_; }
  // Connected component of vertex v (components numbered by their smallest vertex).
  int32_t component(int32_t v) const { return component_[v]; }
  int32_t num_components() const { return num_components_; }

  // distance[k] = heat geodesic distance from `source` to patch[k]; `source` must be
  // in the patch; patch ids distinct and in range (Error(BadUsage) otherwise).
  void query(int32_t source, std::span<const int32_t> patch, std::span<double> distance,
             HeatGeodesicWorkspace& ws) const {
    query(source, patch, distance, ws, opt_.poisson_rhs);
  }
  // The same with the Poisson right-hand side chosen per query (for measuring both).
  void query(int32_t source, std::span<const int32_t> patch, std::span<double> distance, HeatGeodesicWorkspace& ws,
             HeatGeodesicOptions::PoissonRhs rhs) const;
  // Whole mesh with full solves: distance has num_vertices() entries.
  void query_full(int32_t source, std::span<double> distance, HeatGeodesicWorkspace& ws) const;

  // Building blocks shared with the log map (pipelines/include/locus/pipelines/geodesic/logmap.hpp).
  // build_region lists the patch, its one ring and the faces touching the patch
  // (build_region_faces: the faces and their corners' local indices).
  void build_region(std::span<const int32_t> patch, PatchRegion& r) const;
  void build_region_faces(PatchRegion& r) const;
  void release_region(PatchRegion& r) const;
  // From heat values at r.verts (h[k] at r.verts[k]) to distances at the patch,
  // zero at r.verts[source_local]. `heat_plan`, when given, is the exact plan
  // whose outputs were r.verts (the heat step's): the Poisson plan is then
  // taken from its backward set instead of walking the etree again
  // (kernels/include/locus/kernels/solve/solve_plan.hpp, plan_subset_solve_within).
  void distance_from_heat(const PatchRegion& r, std::span<const double> h, int32_t source_local,
                          std::span<double> distance, HeatGeodesicWorkspace& ws,
                          HeatGeodesicOptions::PoissonRhs rhs, const SolvePlan* heat_plan = nullptr) const;
  // Supernode of each vertex in the shared symbolic factor (for planning).
  std::span<const int32_t> vertex_supernodes() const { return vertex_super_; }
  // From heat values at every vertex to distances at every vertex.
  void distance_from_heat_full(std::span<const double> h, int32_t source, std::span<double> distance,
                               HeatGeodesicWorkspace& ws) const;
  // The unshifted solution phi of the Poisson step, into ws.b (n entries): the
  // distance up to a constant per connected component (multi-source queries
  // choose the constants, engine/src/session_geodesic.cpp).
  void potential_from_heat_full(std::span<const double> h, HeatGeodesicWorkspace& ws) const;

 private:
  // Checks and per-mesh data shared by the constructors (the robust one: no manifold checks, intrinsic gradients).
  void prepare(const Mesh& m, const MeshDerived* derived = nullptr, const RobustOperators* robust = nullptr);
  void factor_both(const CscMatrix& A, const CscMatrix& P, const std::shared_ptr<const SymbolicFactor>& S,
                   const RunContext& ctx);
  double dip_tolerance() const { return opt_.dip_tolerance_h * h_; }
  void note_underflow(std::span<const double> h, double h_source, std::span<const double> distance,
                      HeatGeodesicWorkspace& ws) const;
  double rim_cut(const PatchRegion& r, std::span<const double> h, HeatGeodesicWorkspace& ws) const;
  void continue_rim(const PatchRegion& r, const double* hlb, double cut, HeatGeodesicWorkspace& ws) const;

  HeatGeodesicOptions opt_;
  TriangleGradients grad_;
  double h_ = 0, t_ = 0;
  NumericFactor heat_, poisson_;
  HostVector<int32_t> component_;
  int32_t num_components_ = 0;
  // 4 per vertex-face entry (grad_.vf_faces order): that face's corners and the
  // face itself, so a region walks each patch vertex's faces in one contiguous read.
  HostVector<int32_t> vf_corners_;
  HostVector<int32_t> vertex_super_;  // n: supernode of each vertex in the heat factor (solve planning)
  bool shared_symbolic_ = true;        // both factors have the same supernodes (plans carry over)
};

}  // namespace locus
