// The two steps of sampled skinning weights (skinning_weights.hpp, Sampled;
// thesis §3.7.2: weights on a coarse set, propagated to the vertices):
//   cover_samples      a greedy cover of the vertex graph: handle vertices first,
//                      then, in ascending id order, every vertex farther than
//                      `rings` edges from all samples so far becomes one (a vertex
//                      in no face has no neighbours and never does). Every
//                      vertex is then within `rings` edges of a sample;
//                      deterministic.
//   propagate_samples  every other vertex v gets the moving-least-squares
//                      combination (linear basis, Franke and Little's weights
//                      ((rho - d) / (rho d))^2, zero beyond rho) of the rows of the
//                      samples within geodesic (Dijkstra, edge lengths) radius rho
//                      = 2.5 x the cover radius (the largest distance from a vertex to
//                      its nearest sample): linear precision, so smooth weights are
//                      reproduced to second order. Then the natural
//                      neighbourhoods are kept: a weight is set to 0 where it is
//                      negative, or small (< 0.02) while a sample within 1.5 x the
//                      cover radius has it exactly 0; a weight whose samples are
//                      all 0 is 0. Rows are renormalized to sum 1, so they stay
//                      non-negative partitions of unity; samples keep their rows.
// Thread safety: re-entrant; parallel in the caller's arena, deterministic
// (stencils gathered in sample order).
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
  std::vector<int32_t> rough;  // refine_miss > 0: non-sample vertices whose fit misses (ascending)
};

// rows: samples.size() * k exact rows; indicator: empty, or one flag per sample
// whose row is an indicator for want of a cell (its zeros are not kept); out:
// n * k (overwritten). refine_miss > 0: list in `rough` the vertices where a
// stencil sample within 0.7 x the cover radius misses the stencil's weighted
// linear fit of some weight by more than refine_miss (the exact weights jump
// there; the caller computes those rows exactly).
Propagation propagate_samples(const Mesh& m, const Adjacency& adj, std::span<const int32_t> samples,
                              std::span<const double> rows, std::span<const uint8_t> indicator, int32_t k,
                              std::span<double> out, const RunContext& ctx, double refine_miss = 0);

}  // namespace locus
