// The requested vertex count of a remesh by edge collapses (thesis §3.7.1):
// repair sites crowd where the topology needed them (holes, thin strips), so
// the dual can hold a few percent more vertices than requested even after the
// density passes (elephant-with-holes 1,039 of 1,000). The shortest interior
// edges collapse, in passes of disjoint neighborhoods, until the count is
// reached: both endpoints off the boundary, the link condition (their common
// neighbors are exactly the two opposite vertices, each of valence above
// three), the merged vertex at the edge's midpoint projected onto the input,
// no triangle of the merged ring turned more than 60 degrees. A collapse
// under these conditions keeps the genus, the components and the boundary
// loops; the optimization that follows evens the vertices out.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "locus/mesh.hpp"
#include "locus/pipelines/voronoi/triangle_grid.hpp"

namespace locus {

// Collapses edges of `remesh` (its vertices on `input`, grid built over it)
// until it has `target` vertices or no edge may go; `vertex_site` (one entry
// per vertex, or empty) follows the kept vertices. Returns the collapses.
// `pinned` (one entry per vertex, or empty): vertices that neither move nor
// go (a feature's, remesh_features.hpp); a free neighbor collapses into one.
// Which edges go first: Short, the shortest against their vertices' mean
// edge (the crowd of repair sites); Flat, the edges whose two rings are the
// flattest (the largest angle between a ring triangle's normal and the
// ring's), then the shortest, and only collapses that leave every triangle
// of the merged ring at least 20 degrees: the vertices a flat, wide region
// can spare (remesh_rebalance.hpp).
enum class CollapseOrder { Short, Flat };
int32_t collapse_to_count(const Mesh& input, const TriangleGrid& grid, Mesh& remesh, int32_t target,
                          std::vector<int32_t>& vertex_site, std::span<const uint8_t> pinned = {},
                          CollapseOrder order = CollapseOrder::Short);

}  // namespace locus
