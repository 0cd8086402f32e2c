// The two steps of sampled skinning weights (skinning_weights.hpp, Sampled;
// thesis §3.7.2: weights on a coarse set, propagated to the vertices):
//   cover_samples      a greedy cover of the vertex graph: handle vertices first,
//                      then, in ascending id order, every vertex farther than
//                      `rings` edges from all samples so far becomes one. Every
//                      vertex is then within `rings` edges of a sample;
//                      deterministic.
//   propagate_samples  w(v) = sum_s phi_s(v) w_s / sum_s phi_s(v) over the samples s
//                      within geodesic (Dijkstra, edge lengths) radius rho of v, with
//                      Franke and Little's weights phi = ((rho - d) / (rho d))^2:
//                      interpolating (a sample keeps its row), C1 in d, zero beyond
//                      rho. A convex combination: non-negative, rows summing to 1
//                      (renormalized), zeros kept where all samples around are zero.
//                      rho = 2 x the largest distance from a vertex to its nearest
//                      sample, so every vertex sees several samples.
// Thread safety: re-entrant; parallel in the caller's arena, deterministic
// (per-sample balls summed in sample order).
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "locus/mesh.hpp"
#include "locus/run_context.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"

namespace locus {

// first: vertices that must be samples (handle vertices), kept first in order.
std::vector<int32_t> cover_samples(const Adjacency& adj, std::span<const int32_t> first, int32_t rings);

struct Propagation {
  double radius = 0;  // rho
  int64_t ball_entries = 0;
};

// rows: samples.size() * k exact rows; out: n * k (overwritten).
Propagation propagate_samples(const Mesh& m, const Adjacency& adj, std::span<const int32_t> samples,
                              std::span<const double> rows, int32_t k, std::span<double> out, const RunContext& ctx);

}  // namespace locus
