// Edge splits at the thinnest triangles a remesh keeps after its optimization
// (thesis §3.7.1): where the mesh must grade towards a feature smaller than
// its edges (ChineseDragon-10kv's boundary loops of three input vertices,
// 0.04 long against edges of ~5.7), moving vertices cannot open the fan
// around it; a vertex more on each thin triangle's longest edge can. Each
// triangle with an angle below `below_deg`, thinnest first, has its longest
// edge split at the midpoint projected onto the input, when that edge lies in
// two triangles and neither was split in this call (so every split is one
// vertex, two triangles more and the same topology), at most `budget` splits.
// cvt_remesh runs one call, then two optimization rounds, and keeps the
// result when the smallest angle grew (docs/cvt.md).
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "locus/mesh.hpp"
#include "locus/pipelines/voronoi/triangle_grid.hpp"

namespace locus {

// `vertex_site` (one entry per vertex, or empty) gets, for a new vertex, the
// site of the split edge's first endpoint; new vertices are appended. An edge
// between two `pinned` vertices (one entry per vertex, or empty: a feature's
// edge, remesh_features.hpp) is not split. With `boundary_edges` a longest
// edge on the boundary splits too (one triangle more; the new vertex, the
// chord's midpoint projected onto the input, is on a straight boundary's
// curve and near a curved one's: remesh_rebalance.hpp across a strip).
// Returns the splits.
int32_t split_thin(const TriangleGrid& grid, Mesh& remesh, double below_deg, int32_t budget,
                   std::vector<int32_t>& vertex_site, std::span<const uint8_t> pinned = {},
                   bool boundary_edges = false);

// The requested vertex count where the remesh has fewer vertices (cells that
// vanished: a coarse input, or sites close together on a needle fan): the
// longest edges split, boundary edges too, in passes where no triangle is
// split twice, until `target` vertices or no edge can split; the optimization
// that follows evens the vertices out. `vertex_site` and `pinned` as above.
// Returns the splits.
int32_t split_to_count(const TriangleGrid& grid, Mesh& remesh, int32_t target, std::vector<int32_t>& vertex_site,
                       std::span<const uint8_t> pinned = {});

}  // namespace locus
