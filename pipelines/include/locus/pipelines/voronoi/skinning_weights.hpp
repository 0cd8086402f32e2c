// Skinning weights from natural-neighbor coordinates (thesis §3.7.2, "Blend
// skinning", Fig. 3.12): the weight of handle j at vertex v is b_j(v), the
// area-stealing coordinate of v with respect to the handles' heat-Voronoi cells
// (pipelines/include/locus/pipelines/voronoi/natural_neighbor.hpp). A handle is a
// vertex set (one vertex, a list, or the vertices of a bone:
// skinning_handles.hpp) whose heat has a unit source at each of its vertices.
// Weights are non-negative, sum to 1 per vertex, are the indicator on a handle's
// vertices, and are exactly 0 for handles whose cells the vertex's cell does not touch.
//
// Two methods:
//   Exact    one heat solve per vertex (8 vertices per solve, 3 solves per
//            pass over the factor, passes in parallel, one slot per vertex:
//            deterministic for any thread count; the forward substitution runs
//            over the 8 sources' etree paths only, the values are the full
//            solve's bit for bit), plus one pass over the vertices
//            per batch for the 8 cells and a re-split of each cell's border
//            triangles. The cost grows with n^2 / handles (a vertex's cell covers
//            a fixed share of its handle's cell: a third of armadillo's vertices
//            with 4 handles), as the thesis notes (§3.7.2: "comparably slow").
//   Sampled  the thesis' way out (§3.7.2: compute on a coarse set, propagate):
//            the exact coordinates at a greedy cover of the vertex graph (every
//            vertex within `rings` edges of a sample, handle vertices first), then
//            propagated to the other vertices by moving least squares over the
//            samples within a geodesic radius (skinning_sampled.hpp). The rows stay
//            non-negative, sum to 1 (renormalized to rounding), handle vertices
//            keep their indicator, and a weight is exactly 0 where the samples
//            around have it 0 (the support is never widened past the samples'
//            zeros; it may shrink by up to the cover radius where the weight is
//            below 0.02). The exact rows themselves jump between neighbouring
//            vertices where edges are long against the diffusion length sqrt(t)
//            (docs/skinning.md), more than a smooth interpolant follows: the
//            vertices where the samples around miss their linear fit by more
//            than `refine_miss`, and probes between adjacent samples whose rows
//            differ, get their exact rows, and so do, round by round, the
//            neighbours of every such vertex whose exact row differs from its
//            propagated one by more than that (skinning_refine.hpp), within a
//            budget of exact rows that shrinks as 1/n (an exact row costs O(n)).
//            A mesh of at most `exact_up_to` vertices (default 10,000) or 3 x the
//            sample target takes exact rows everywhere (method "exact"): there all
//            rows cost about as many as the cover and the refinement's budget
//            together, under a second (docs/skinning.md). Cost: at most `samples` cover rows plus
//            the refined ones (exact rows as above) plus O(n) propagation; a
//            propagated weight below 1e-3 of its row's largest is 0.
// Large meshes: the front ends take the coarse road of skinning_coarse.hpp
// (the sampled method on a coarse level, propagated) instead of Sampled.
#pragma once
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "locus/mesh.hpp"
#include "locus/run_context.hpp"
#include "locus/kernels/heat/heat_diffusion.hpp"
#include "locus/kernels/heat/surface_point.hpp"

namespace locus {

enum class SkinningMethod : uint8_t { Sampled, Exact };

struct SkinningOptions {
  SkinningMethod method = SkinningMethod::Sampled;
  // Sampled: the most sample vertices (the greedy cover with the smallest radius
  // in edges that has at most this many; handle vertices are always samples);
  // 0 = the default 1024. More samples: closer to Exact, slower.
  int32_t samples = 0;
  // Sampled: vertices where the samples around miss their linear fit by more than
  // this (the exact weights jump between them) get their exact row too, with the
  // probes and growth of skinning_refine.hpp; 0 = off (and no small-mesh exact road).
  double refine_miss = 0.05;
  // Sampled with refinement: a mesh of at most this many vertices takes exact rows
  // everywhere (n rows of O(n) each; camel, 9,770 vertices: 1.5-1.9x the sampled
  // road's time, under a second on a quiet machine); 0 = only by the sample
  // target (at most 3 x samples).
  int32_t exact_up_to = 10000;
};

struct SkinningWeights {
  int32_t handles = 0;
  std::vector<double> weight;  // n * handles, row-major (vertex v's weights at v * handles)
  int64_t degenerate = 0;      // vertices whose cell held no vertex (indicator of the containing cell)
  int64_t fallback_faces = 0;  // summed over vertices
  double max_clamped = 0;      // largest relative negative area difference clamped to 0
  std::string method;          // "exact" or "sampled"
  int32_t samples = 0;         // vertices whose row is exact (all for Exact; Sampled: cover + refined)
  int32_t refined = 0;         // Sampled: of those, the vertices refined where the fit missed
  int32_t sample_rings = 0;    // Sampled: every vertex is within this many edges of a sample
  double radius = 0;           // Sampled: the propagation radius (length units)
  int32_t coarse_vertices = 0; // coarse road (skinning_coarse.hpp): vertices of the coarse level, else 0
  double t = 0;                // coarse road: the coarse operator's diffusion time, else 0
  double factor_s = 0;         // coarse road: the coarse operator's factorization
  double prepare_s = 0, weights_s = 0, propagate_s = 0;
};

// H: prepared heat operator of m; handles: at least one, valid surface points
// (each its own site). Exact per-vertex computation.
SkinningWeights skinning_weights(const HeatDiffusion& H, const Mesh& m, std::span<const SurfacePoint> handles,
                                 const RunContext& ctx);

// handles: vertex sets (non-empty, disjoint, valid ids), one per handle.
SkinningWeights skinning_weights(const HeatDiffusion& H, const Mesh& m, std::span<const std::vector<int32_t>> handles,
                                 const SkinningOptions& options, const RunContext& ctx);

}  // namespace locus
