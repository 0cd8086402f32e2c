// Refinement of sampled skinning weights (skinning_weights.hpp, Sampled; thesis
// §3.7.2): exact rows where the propagation from the cover samples cannot follow
// the exact weights, which jump and kink between neighbouring vertices where the
// edges are long against the diffusion length (docs/skinning.md). In order:
//   seeds    the vertices `rough` (their samples miss the stencil's linear fit)
//            and probes on the borders between adjacent samples' regions (nearest
//            sample in edges) where the two samples' rows differ by more than
//            1.4 x miss, the largest differences first, none within 2 edges of a
//            rough vertex or an earlier probe: the kinks lie between samples,
//            where no test on the samples alone can see them;
//   growth   round by round, the not yet exact neighbours of every vertex whose
//            exact row differs from its propagated one by more than `miss`;
//   closing  up to 4 rounds: vertices with 3/4 of their neighbours exact, or an
//            exact neighbour whose row differs from theirs by more than 1.2 x miss
//            (an isolated exact row differs from all its neighbours'), then growth;
//   last     growth at 0.6 x miss from every exact row that missed by more;
//   skinny   with the budget left, the open vertices of `irregular` (corners of
//            an angle under 10 degrees: skinny_corners) and growth at 0.6 x miss:
//            the exact rows jump at such corners without a sign on the samples;
//   correct  every propagated row moves by the exact rows' residuals (exact
//            minus propagated) within 2 rings, weight by weight the residual of
//            least magnitude where all agree in sign, else not at all (minmod:
//            it never passes the nearest exact rows' own correction, so it does
//            not carry a jump across; a sample there has residual 0 and stops
//            it); only weights > 0 move, and the gains or the losses, whichever
//            are larger, are scaled to the other side's total (the row keeps its
//            sum: a residual on a weight at 0, which does not move, is not handed
//            to the others); negatives go to 0, rows renormalized to rounding;
//   zeros    a propagated weight under 0.01 where a neighbour's row (exact or
//            propagated, not a handle's or a degenerate indicator) has it 0 is 0,
//            row renormalized: one ring off the support's edge for tiny weights
//            only. Where a natural neighbourhood ends within the cover radius the
//            samples around carry a tail of the weight past its border (the
//            propagation keeps only the cover samples' zeros); this stops it.
// Every growth round after the seeds keeps the exact rows (samples included) at
// most `row_budget`: a front over it keeps the neighbours of the largest misses.
// Deterministic: every front is sorted by vertex id (a truncated one is chosen by
// miss, then id) before it is solved.
#pragma once
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "locus/mesh.hpp"
#include "locus/kernels/mesh/mesh_topology.hpp"
#include "locus/pipelines/voronoi/skinning_weights.hpp"

namespace locus {

// Exact rows of `verts` into rows (verts.size() * k); one indicator flag per vertex.
using SolveSkinRows = std::function<void(std::span<const int32_t> verts, std::vector<double>& rows,
                                         std::vector<uint8_t>& indicator)>;

// W.weight: the propagated weights with the samples' exact rows (overwritten with
// exact rows where refined, then corrected); sample_rows: samples.size() * k;
// sample_indicator: per sample, its row is an indicator for want of a cell; irregular: ascending vertex ids; owner: per vertex,
// the handle it belongs to or -1 (never refined). Adds the refined count to W.refined.
void refine_sampled_rows(const Adjacency& adj, std::span<const int32_t> samples, std::span<const double> sample_rows,
                         std::span<const uint8_t> sample_indicator, std::span<const int32_t> rough,
                         std::span<const int32_t> irregular, std::span<const int32_t> owner, double miss,
                         int64_t row_budget, const SolveSkinRows& solve_rows, SkinningWeights& W);

// The step `correct` above: exact flags the rows that are exact (or handle
// indicators); interp: the propagated rows (n * k); W.weight: the exact rows where
// exact, the propagated ones elsewhere (those are replaced).
void correct_propagated_rows(const Adjacency& adj, std::span<const uint8_t> exact, std::span<const double> interp,
                             SkinningWeights& W);

// The step `zeros` above: in every row not flagged `exact`, a weight in (0, below)
// set to 0 where a neighbour flagged `zero_source` has it exactly 0 (the rows as
// they come in: the result does not depend on the vertex order); such rows
// renormalized (a row whose weights would all go keeps them).
void keep_neighbour_zeros(const Adjacency& adj, std::span<const uint8_t> exact, std::span<const uint8_t> zero_source,
                          double below, SkinningWeights& W);

// Vertices (ascending) at a face corner whose angle is under max_angle_deg.
std::vector<int32_t> skinny_corners(const Mesh& m, double max_angle_deg);

}  // namespace locus
