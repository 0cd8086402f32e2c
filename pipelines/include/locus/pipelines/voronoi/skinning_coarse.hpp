// Skinning weights on a coarse level of a large mesh (thesis §3.7.2: "compute
// the weights on a coarse mesh and propagate them"; the coarse mesh is the
// restricted-Delaunay dual of §3.7.1):
//   level      a greedy vertex cover (skinning_sampled.hpp, handle vertices
//              first) of at most kSkinCoarseVertices sites, their graph-geodesic
//              Voronoi cells (one multi-source Dijkstra), repaired by adding
//              sites until the cells' dual is a manifold (restricted_dual.hpp),
//              and that dual as a mesh whose vertices are fine vertices.
//   weights    the sampled natural-neighbour weights on the coarse mesh, with
//              its own heat operator (t in units of its own h^2), the handles
//              as the coarse vertices of their vertices.
//   propagate  each fine vertex takes the barycentric combination of the rows
//              of the coarse triangle it projects into (among the triangles
//              around the cells of its one-ring; inside one, else the least
//              outside, coordinates clamped to >= 0); coarse vertices and
//              handle vertices keep their rows.
// The properties hold by construction: a convex combination of non-negative
// partitions of unity (renormalized to rounding), handle rows the indicator,
// and a weight exactly 0 where the three corners' weights are 0 (the coarse
// natural neighbourhoods). The fine mesh is never factored: the cost is the
// coarse level's (bounded) plus O(n) for the cover, cells, dual and
// propagation, so it does not grow with the square of n.
// Thread safety: re-entrant.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "locus/mesh.hpp"
#include "locus/pipelines/voronoi/skinning_weights.hpp"
#include "locus/run_context.hpp"

namespace locus {

// The coarse level's vertex budget; meshes with more than four times as many
// vertices take the coarse road (skinning_uses_coarse_level; smaller ones the
// fine sampled method, closer to the exact weights and fast enough there).
constexpr int32_t kSkinCoarseVertices = 12000;

// Sampled weights of a mesh with more than 4 x kSkinCoarseVertices vertices.
bool skinning_uses_coarse_level(int32_t n, const SkinningOptions& options);

// m: a clean manifold triangle mesh; handles: disjoint non-empty vertex sets;
// t_factor / t_abs: the coarse operator's time (t_abs > 0: absolute, else
// t_factor * h_coarse^2). Fills method "coarse", samples (exact rows on the
// coarse level), coarse_vertices, and the timings (factor_s: the coarse operator).
SkinningWeights skinning_weights_coarse(const Mesh& m, std::span<const std::vector<int32_t>> handles,
                                        const SkinningOptions& options, double t_factor, double t_abs,
                                        const RunContext& ctx);

}  // namespace locus
